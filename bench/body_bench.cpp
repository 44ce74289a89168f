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

// The same, dressed: a suit, shoes, hair and eyebrows fitted through their .mhclo proxies.
void BM_BuildClothedPerson(benchmark::State& state) {
  const auto& d = data();
  std::uint64_t seed = 0;
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto spec = wheelpose::body::sample_spec(seed++ % 64);
    spec.proxies = {
        spec.params.gender >= 0.5 ? "clothes/male_casualsuit01" : "clothes/female_casualsuit01",
        "clothes/shoes01", "hair/short02", "eyebrows/eyebrow001"};
    const auto person = wheelpose::body::build_person(d, spec);
    bytes = person.vertices.size() * sizeof(Eigen::Vector3f) * 2;
    for (const auto& g : person.garments)
      bytes += g.vertices.size() * sizeof(Eigen::Vector3f) * 2 + g.triangles.size() * 12;
    benchmark::DoNotOptimize(person.vertices.data());
  }
  state.counters["bytes_per_person"] = static_cast<double>(bytes);
}
BENCHMARK(BM_BuildClothedPerson)->Unit(benchmark::kMillisecond);

}  // namespace
