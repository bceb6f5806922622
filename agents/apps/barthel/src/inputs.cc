// The simulated sensors of the patient: speech recognition, touches and presence, read from the `sim_patient`
// node's ground truth.
#include "quiver/agents/apps/barthel/inputs.h"

#include "quiver/agents/apps/barthel/barthel_schema.h"

namespace quiver::agents::inline apps::barthel {
namespace {

graph::NodeId patient_node(const graph::Graph* g) {
  return g ? node_id(*g, node::kSimPatient) : graph::NodeId{};
}

class SimSpeech final : public SpeechInput {
 public:
  explicit SimSpeech(TruthSource t) : truth_(std::move(t)) {}
  std::optional<Heard> last(const graph::Graph& own) override {
    const graph::Graph* g = truth_ ? truth_() : &own;
    graph::NodeId p = patient_node(g);
    if (p.is_null() || attr_int(*g, p, "said_seq") <= 0) return std::nullopt;
    return Heard{attr_int(*g, p, "said_seq"), attr_string(*g, p, "said_text"), attr_int(*g, p, "said_for", -1)};
  }

 private:
  TruthSource truth_;
};

class SimTouch final : public TouchInput {
 public:
  explicit SimTouch(TruthSource t) : truth_(std::move(t)) {}
  std::optional<Touch> last(const graph::Graph& own) override {
    const graph::Graph* g = truth_ ? truth_() : &own;
    graph::NodeId p = patient_node(g);
    if (p.is_null() || attr_int(*g, p, "tap_seq") <= 0) return std::nullopt;
    return Touch{attr_int(*g, p, "tap_seq"), static_cast<int>(attr_int(*g, p, "tap_option", -1)),
                 attr_int(*g, p, "tap_for", -1)};
  }

 private:
  TruthSource truth_;
};

class SimPresence final : public PersonSensor {
 public:
  explicit SimPresence(TruthSource t) : truth_(std::move(t)) {}
  std::optional<bool> present(const graph::Graph& own) override {
    const graph::Graph* g = truth_ ? truth_() : &own;
    graph::NodeId p = patient_node(g);
    if (p.is_null() || !g->attr(p, "present")) return std::nullopt;
    return attr_bool(*g, p, "present");
  }

 private:
  TruthSource truth_;
};

}  // namespace

std::unique_ptr<SpeechInput> simulated_speech_input(TruthSource truth) {
  return std::make_unique<SimSpeech>(std::move(truth));
}
std::unique_ptr<TouchInput> simulated_touch_input(TruthSource truth) {
  return std::make_unique<SimTouch>(std::move(truth));
}
std::unique_ptr<PersonSensor> simulated_person_sensor(TruthSource truth) {
  return std::make_unique<SimPresence>(std::move(truth));
}

}  // namespace quiver::agents::inline apps::barthel
