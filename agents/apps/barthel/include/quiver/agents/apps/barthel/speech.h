#pragma once
/// @file
/// The Speech agent (seed 000): says what the Planner puts on `test -[say]-> u`, one utterance at
/// a time, marking `speaker -[speaking]-> u` while it speaks and `speaker -[spoke]-> u` when the
/// sentence has been said to the end. It speaks to the patient only while the person sensor says
/// someone is there (the `in_front_of` edge, and a reading no older than `presence_stale_ns`):
/// the person lost mid-sentence cancels the action, the audio stops at once and the mark goes
/// back to not speaking. It also runs speech recognition and writes what the patient answered as
/// `speaker -[heard]-> u` on the question it answers. Grammar: grammars/speech.aggl.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "quiver/agents/apps/barthel/inputs.h"
#include "quiver/agents/devices/speech_output.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::barthel {

struct SpeechOptions {
  std::int64_t presence_stale_ns = 250'000'000;
  std::int64_t asr_period_ns = 20'000'000;
  std::int64_t lock_priority = 1;  ///< on the speaker
};

/// One stop of the audio because the person was lost: when Person committed the loss
/// (person.lost_ns) and when the audio stopped, on the agents' shared clock.
struct Reaction {
  std::int64_t lost_ns = 0;
  std::int64_t stopped_ns = 0;
};

class Speech final : public Agent {
 public:
  Speech(std::unique_ptr<devices::SpeechOutput> out, std::unique_ptr<SpeechInput> in,
         SpeechOptions o = {}, std::string name = "speech");
  ~Speech() override;
  void setup(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;

  devices::SpeechOutput& output() { return *out_; }
  /// Called each time the audio stops because the person was lost.
  void on_reaction(std::function<void(const Reaction&)> cb) { reaction_cb_ = std::move(cb); }

 private:
  class Speak;
  void poll_asr(AgentContext& ctx);
  std::unique_ptr<devices::SpeechOutput> out_;
  std::unique_ptr<SpeechInput> in_;
  SpeechOptions opt_;
  std::function<void(const Reaction&)> reaction_cb_;
  std::int64_t handled_heard_ = 0;
  std::uint64_t spoken_ = 0, interrupted_ = 0, heard_ = 0;
  std::int64_t last_reaction_ns_ = -1;
  static constexpr std::size_t kMaxReactionsKept = 100'000;
  std::vector<std::int64_t> reactions_ns_;  ///< each stop since start (status: reactions_us)
};

/// The option of `options` that `text` names (case-insensitive; the longest label contained in
/// the text wins), or -1.
int match_option(std::string_view text, const std::vector<std::string>& options);

}  // namespace quiver::agents::inline apps::barthel
