// The C++ reference for python/bench/writes.py: the same workload (random double writes to
// `nodes` x `attrs` attributes in transactions of `batch`) run by a C++ loop, so the Python
// per-call overhead can be measured against it.

#include <chrono>

#include "common.h"
#include "quiver/base/rng.h"

namespace quiver::python {

void bind_bench(py::module_& m) {
  m.def("_bench_cpp_writes", [](std::size_t nodes, std::size_t attrs, std::size_t writes, std::size_t batch,
                                std::uint64_t seed) {
        py::gil_scoped_release release;
        graph::Graph g(graph::ReplicaId{1, 1});
        std::vector<graph::NodeId> ids;
        std::vector<graph::Symbol> names;
        for (std::size_t a = 0; a < attrs; ++a) names.emplace_back("a" + std::to_string(a));
        {
          auto t = g.begin();
          for (std::size_t n = 0; n < nodes; ++n) {
            std::vector<std::pair<graph::Symbol, graph::Value>> init;
            for (graph::Symbol s : names) init.emplace_back(s, graph::Value(0.0));
            ids.push_back(t.create_node("thing", "n" + std::to_string(n), std::move(init)).value());
          }
          (void)t.commit();
        }
        // Draw the random choices first, as the Python script does.
        Rng rng(seed);
        std::vector<std::uint32_t> node_ix(writes), attr_ix(writes);
        std::vector<double> vals(writes);
        for (std::size_t i = 0; i < writes; ++i) {
          node_ix[i] = static_cast<std::uint32_t>(rng.below(nodes));
          attr_ix[i] = static_cast<std::uint32_t>(rng.below(attrs));
          vals[i] = rng.uniform();
        }
        auto start = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i < writes;) {
          auto t = g.begin();
          for (std::size_t k = 0; k < batch && i < writes; ++k, ++i)
            (void)t.set(ids[node_ix[i]], names[attr_ix[i]], graph::Value(vals[i]));
          auto r = t.commit();
          if (!r.ok()) throw std::runtime_error(r.error().to_string());
        }
        std::chrono::duration<double> s = std::chrono::steady_clock::now() - start;
        return static_cast<double>(writes) / s.count();
      },
      py::arg("nodes") = 1000, py::arg("attrs") = 10, py::arg("writes") = 200000, py::arg("batch") = 100,
      py::arg("seed") = 1, "Writes per second of the bench workload run in C++ (the reference for writes.py).");
}

}  // namespace quiver::python
