#pragma once
// Helpers of the interop tests: fixture paths and short reads of an imported graph.

#include <gtest/gtest.h>

#include <string>

#include "quiver/graph/graph.h"
#include "quiver/interop/interop.h"

namespace quiver::interop::testing {

/// A file under tests/graph/interop/fixtures.
inline std::string fixture(const std::string& rel) { return std::string(QUIVER_INTEROP_FIXTURES) + "/" + rel; }

/// The node of that name (a test failure if there is none).
inline graph::NodeId node(const graph::Graph& g, const std::string& name) {
  auto id = g.find_node(name);
  EXPECT_TRUE(id.has_value()) << "no node '" << name << "'";
  return id.value_or(graph::NodeId{});
}

/// The value of a node attribute (a test failure if it has none).
inline graph::Value attr(const graph::Graph& g, const std::string& n, const std::string& a) {
  const graph::Value* v = g.attr(node(g, n), a);
  EXPECT_NE(v, nullptr) << n << "." << a;
  return v ? *v : graph::Value();
}

/// Whether a warning of the report contains `part`.
inline bool has_warning(const ImportReport& r, const std::string& part) {
  for (const auto& w : r.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

using ImportFn = Result<ImportReport> (*)(graph::Graph&, std::string_view, std::string_view, const ImportOptions&);

/// The message of a refused import of `text` named `source` (a test failure if it is accepted, or
/// if it added anything).
inline std::string refusal(ImportFn import, const std::string& text, const std::string& source) {
  graph::Graph g(graph::ReplicaId{1, 1});
  auto r = import(g, text, source, {});
  EXPECT_FALSE(r.ok()) << source << " is accepted";
  EXPECT_EQ(g.node_count(), 0u) << source << ": a refused file added nothing";
  return r.ok() ? "" : r.error().message;
}

/// Whether `text` imports (the error's message when not: "" when it does).
inline std::string acceptance(ImportFn import, const std::string& text, const std::string& source) {
  graph::Graph g(graph::ReplicaId{1, 1});
  auto r = import(g, text, source, {});
  return r.ok() ? "" : r.error().message;
}

/// The same for a fixture file (named by its path).
inline std::string file_refusal(ImportFn import, const std::string& rel) {
  auto text = read_file("file_refusal()", fixture(rel));
  EXPECT_TRUE(text.ok()) << rel;
  return refusal(import, text.ok() ? *text : "", fixture(rel));
}

}  // namespace quiver::interop::testing
