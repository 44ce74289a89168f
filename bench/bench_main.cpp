// The main() of every bench_<name>: Google Benchmark's, after the command's own heap tuning
// (core/allocator.h), so figures match what `wheelpose` does.

#include <benchmark/benchmark.h>

#include "core/allocator.h"

int main(int argc, char** argv) {
  wheelpose::retain_freed_memory();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
