#pragma once
/// @file
/// A readable transcript of a Barthel test, written by watching the graph only (as any observer
/// replica can): what the robot said to the end or was interrupted saying, what the patient
/// answered and how, the person leaving and coming back, the clinician paged, the result.
#include <cstdint>
#include <functional>
#include <set>
#include <string>

#include "quiver/graph/graph.h"

namespace quiver::agents::inline apps::barthel {

class Transcript {
 public:
  /// `out` gets one line per event.
  Transcript(const graph::Graph& g, std::function<void(const std::string&)> out) : g_(g), out_(std::move(out)) {}
  /// Feed every change batch of the graph (Graph::subscribe).
  void on_changes(const graph::ChangeBatch& b);
  std::string status() const { return status_; }
  int item() const { return item_; }
  bool goodbye_said() const { return goodbye_said_; }
  /// Sentences the robot stopped before their end (the speaking mark taken back, never spoken).
  int interruptions() const { return interruptions_; }

 private:
  const graph::Graph& g_;
  std::function<void(const std::string&)> out_;
  std::set<std::int64_t> said_, answered_;
  std::string status_;
  int item_ = -1;
  int interruptions_ = 0;
  bool present_ = false, seen_presence_ = false, goodbye_said_ = false, called_ = false;
};

}  // namespace quiver::agents::inline apps::barthel
