// The transcript of a Barthel test, one line per event, read from the graph's change batches only.
#include "quiver/agents/apps/barthel/transcript.h"

#include "quiver/agents/apps/barthel/barthel_schema.h"

namespace quiver::agents::inline apps::barthel {

using graph::ChangeKind;
using graph::Symbol;

void Transcript::on_changes(const graph::ChangeBatch& b) {
  const Symbol spoke(edge::kSpoke), speaking(edge::kSpeaking), heard(edge::kHeard), tapped(edge::kTapped),
      calls(edge::kCalls), in_front(edge::kInFrontOf);
  for (const graph::EdgeChange& e : b.edges) {
    if (e.key.type == spoke && e.kind == ChangeKind::kCreated) {
      auto p = prompt_at(g_, e.key.to);
      if (p && said_.insert(p->seq).second) {
        out_("robot:   " + p->text);
        if (p->purpose == "goodbye" || p->purpose == "clinician") goodbye_said_ = true;
      }
    } else if (e.key.type == speaking && e.kind == ChangeKind::kDeleted) {
      auto p = prompt_at(g_, e.key.to);
      if (p && !marked(g_, node::kSpeaker, edge::kSpoke, p->id)) {
        ++interruptions_;
        out_("robot:   (stops mid-sentence: \"" + p->text.substr(0, 40) + "...\")");
      }
    } else if ((e.key.type == heard || e.key.type == tapped) && e.kind == ChangeKind::kCreated) {
      auto p = prompt_at(g_, e.key.to);
      auto a = answer_to(g_, e.key.to);
      if (p && a && answered_.insert(p->seq).second) {
        const bool voice = e.key.type == heard;
        std::string what = voice ? "patient: \"" + a->text + "\"" : "patient: (touches \"" + a->text + "\")";
        if (a->option < 0) what += "   [not understood]";
        out_(what);
      }
    } else if (e.key.type == calls && e.kind == ChangeKind::kCreated && !called_) {
      called_ = true;
      out_("*** the clinician is paged (two items unanswered)");
    } else if (e.key.type == in_front && (e.kind == ChangeKind::kCreated || e.kind == ChangeKind::kDeleted)) {
      const bool now = e.kind == ChangeKind::kCreated;
      if (seen_presence_ && now == present_) continue;
      if (seen_presence_ || now) out_(now ? "*** the patient sits in front of the robot" : "*** the patient leaves the chair");
      present_ = now;
      seen_presence_ = true;
    }
  }
  graph::NodeId test = node_id(g_, node::kTest);
  if (test.is_null()) return;
  const std::string status = attr_string(g_, test, "status");
  const int item = static_cast<int>(attr_int(g_, test, "item", -1));
  if (status == "running" && item != item_ && attr_string(g_, test, "phase") != "intro") {
    item_ = item;
  }
  if (status != status_) {
    status_ = status;
    if (status == "done" || status == "clinician_called")
      out_("*** test " + status + ": " + std::to_string(attr_int(g_, test, "total")) + " of 100 points");
  }
}

}  // namespace quiver::agents::inline apps::barthel
