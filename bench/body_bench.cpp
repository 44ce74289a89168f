// Building one posed, skinned person in a fitted wheelchair once the shared model is loaded.
// Run: build/<dir>/bench/bench_body

#include <benchmark/benchmark.h>

#include "body/person.h"

namespace {

const wheelpose::body::BodyData& data() {
  static const auto* d = [] {
    auto* loaded =
        new wheelpose::body::BodyData(std::filesystem::path(WHEELPOSE_SHARED_DIR) / "assets");
    loaded->model().preload_all();
    return loaded;
  }();
  return *d;
}

void BM_BuildPerson(benchmark::State& state) {
  const auto& d = data();
  std::uint64_t seed = 0;
  std::size_t bytes = 0;
  for (auto _ : state) {
    const auto person = wheelpose::body::build_person(d, wheelpose::body::sample_spec(seed++ % 64));
    bytes = person.vertices.size() * sizeof(Eigen::Vector3f) * 2 +
            person.chair.parts.size() * sizeof(wheelpose::body::Primitive) +
            person.description.dump().size();
    benchmark::DoNotOptimize(person.vertices.data());
  }
  state.counters["bytes_per_person"] = static_cast<double>(bytes);
}
BENCHMARK(BM_BuildPerson)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
