#pragma once
// The C++ Action an agent owns for a Python quiver.Action: it keeps the Python object alive and
// forwards every call to it.

#include "common.h"
#include "quiver/agents/runtime/api/action.h"

namespace quiver::python {

class ForwardingAction final : public agents::Action {
 public:
  /// @pre `action` is a quiver.Action (its C++ part outlives this: this keeps a reference).
  explicit ForwardingAction(py::object action);
  ~ForwardingAction() override;  // lets go of the Python object with the GIL
  ForwardingAction(const ForwardingAction&) = delete;
  ForwardingAction& operator=(const ForwardingAction&) = delete;

  std::vector<agents::Match> find(agents::AgentContext& ctx) override { return target_->find(ctx); }
  bool holds(agents::AgentContext& ctx, const agents::Match& m) override {
    return target_->holds(ctx, m);
  }
  std::optional<agents::LockNeed> lock(agents::AgentContext& ctx, const agents::Match& m) override {
    return target_->lock(ctx, m);
  }
  Status start(agents::AgentContext& ctx, const agents::Match& m) override {
    return target_->start(ctx, m);
  }
  agents::Progress process(agents::AgentContext& ctx, const agents::Match& m) override {
    return target_->process(ctx, m);
  }
  Status finish(agents::AgentContext& ctx, const agents::Match& m) override {
    return target_->finish(ctx, m);
  }
  void cancel(agents::AgentContext& ctx, const agents::Match& m,
              agents::CancelReason why) override {
    target_->cancel(ctx, m, why);
  }

 private:
  agents::Action* target_;
  py::object* keep_;
};

}  // namespace quiver::python
