// Ablation of the sequential backend's priority queue: the same Dijkstra engine and packed keys,
// with the radix heap it ships, a binary heap with lazy deletion (std::priority_queue) and an ordered
// set with erase/insert decrease-key (std::set, SOFA's choice). Names: queue/<kind>/gradient/<n>.
#include <benchmark/benchmark.h>
#include <geovoronoi.hpp>

#include <functional>
#include <queue>
#include <set>
#include <vector>

namespace gv = geovoronoi;
namespace {

using kt = gv::detail::search::key_traits<float>;
using item = gv::detail::search::radix_heap<float>::item;

struct binary_heap {
  struct later {
    bool operator()(const item& a, const item& b) const { return b.key < a.key; }
  };
  std::priority_queue<item, std::vector<item>, later> q;
  bool empty() const { return q.empty(); }
  void push(kt::key_type k, gv::index_t v) { q.push({k, v}); }
  item pop() {
    item x = q.top();
    q.pop();
    return x;
  }
};

// std::set keeps one entry per voxel: a decrease-key erases the old entry. Stale entries never exist,
// so the engine's stale check always passes.
struct ordered_set {
  std::set<std::pair<kt::key_type, gv::index_t>> s;
  std::vector<kt::key_type>* current = nullptr;
  bool empty() const { return s.empty(); }
  void push(kt::key_type k, gv::index_t v) {
    const auto old = (*current)[std::size_t(v)];
    if (old != kt::unreached) s.erase({old, v});
    (*current)[std::size_t(v)] = k;
    s.insert({k, v});
  }
  item pop() {
    const auto x = *s.begin();
    s.erase(s.begin());
    return {x.first, x.second};
  }
};

template <class Heap>
void run_queue(benchmark::State& state) {
  const int n = int(state.range(0));
  const gv::grid<3> g({n, n, n});
  const auto field = gv::phantom::gradient(g);
  const auto p = gv::make_problem(g, field, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto seeds = gv::phantom::random_seeds(field, 10, 7);
  for (auto _ : state) {
    std::vector<gv::detail::search::node<float>> work(std::size_t(g.size()));
    for (gv::index_t v = 0; v < g.size(); ++v) work[v].set_key(kt::unreached), work[v].field = field[v];
    gv::detail::search::dense_keys<float> st{work.data()};
    Heap heap;
    std::vector<kt::key_type> shadow;
    if constexpr (std::is_same_v<Heap, ordered_set>) {
      shadow.assign(std::size_t(g.size()), kt::unreached);
      heap.current = &shadow;
    }
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      const auto v = g.index(seeds[i]);
      const auto k = kt::make(0.0f, gv::label_t(i));
      st.set(v, k);
      heap.push(k, v);
    }
    const auto settled = gv::detail::search::run(p, st, heap, [](gv::index_t, float) { return true; });
    benchmark::DoNotOptimize(settled);
  }
  state.counters["voxels_per_second"] =
      benchmark::Counter(double(g.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK_TEMPLATE(run_queue, gv::detail::search::radix_heap<float>)
    ->Name("queue/radix_heap/gradient")->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(run_queue, binary_heap)
    ->Name("queue/binary_heap/gradient")->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(run_queue, ordered_set)
    ->Name("queue/std_set/gradient")->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
