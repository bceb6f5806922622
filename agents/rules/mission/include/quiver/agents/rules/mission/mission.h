#pragma once
/// @file
/// Missions: what the world should look like, as AGM's `.aggt` targets say it (docs/planner.md).
///
///     {
///       1:robot(0,0)          a name starting with a digit: a CONSTANT, the world node with that
///       20:table              AGM id (`agm_id`, as import-agm keeps it) or, failing that, name
///       obj:object            any other name: a VARIABLE (some node of the type, or a subtype)
///       1->20(know)
///       obj->20(in)
///       3->1(block)*          '*': the link must NOT exist
///     }
///     precondition { (forall o:object (when (in o 20) (= o obj))) }
///
/// A mission holds when an injective assignment of its variables (constants fixed) has every
/// link present, every negated link absent, and the formula (AGM's s-expressions: and, or,
/// not, links, =, forall, exists, when) true.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/symbolic/match.h"
#include "quiver/agents/rules/symbolic/state.h"
#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline rules {

struct Mission {
  std::string source;              ///< file name, for messages
  Pattern pattern;                 ///< nodes (constants and variables) and links
  std::vector<bool> constant;      ///< per pattern node: a constant (a world node)
  std::optional<Formula> formula;  ///< AGM's `precondition { }` of a target
  std::vector<std::string> notes;  ///< what was read with AGM's tolerance (e.g. trailing text)
  bool is_constant(std::string_view var) const;
};

/// Parses an AGM target (`.aggt`). The text may be empty (a mission that always holds).
/// @returns kMalformed naming "source:line:column: expected ..., found ..." on bad input.
Result<Mission> parse_mission(std::string_view text, std::string_view source = "mission");
/// Reads and parses a `.aggt` file. @returns kIo if it cannot be read, else as parse_mission().
Result<Mission> load_mission_file(const std::string& path);

/// What check_mission() found.
struct MissionReport {
  bool holds = false;
  /// When it holds: variable -> node label (AGM id or name) of a satisfying assignment. When
  /// not: the assignment that satisfies the most nodes and links (unmatched variables absent).
  std::vector<std::pair<std::string, std::string>> binding;
  /// What is missing under that assignment, one line each: nodes no world node matches, links
  /// absent (or present though negated), the formula false.
  std::vector<std::string> missing;
  int satisfied = 0, total = 0;  ///< nodes and links satisfied / in the mission
  bool exhaustive = true;        ///< false: the search for the best assignment hit its budget
};

/// A mission compiled against a problem's vocabulary: what planners test on every state.
struct CompiledMission {
  symbolic::CPattern pattern;
  std::optional<symbolic::CFormula> formula;
  int slots = 0;
  symbolic::Binding prebound;  ///< constants bound, variables kNoNode
  /// Constants that name no world node (nor a node a plan could create): never satisfiable.
  std::vector<std::string> unresolved;
};

/// Compiles `m` for `world` (constants resolved through World::find). Types and labels are
/// interned in `world.vocabulary`.
/// @returns kInvalidArgument when the formula reads attributes (a symbolic state has none).
Result<CompiledMission> compile_mission(const Mission& m, symbolic::World& world);

/// True if `m` holds in `s`; `binding` receives the satisfying assignment.
bool mission_holds(const symbolic::State& s, const symbolic::Vocabulary& voc,
                   const CompiledMission& m, symbolic::Binding* binding = nullptr);

/// Checks `m` against a replica. `types` gives type inheritance (a domain grammar's).
/// @param budget bounds the search for the best partial assignment (nodes visited).
MissionReport check_mission(const Mission& m, const graph::Graph& g, const TypeSystem& types = {},
                            std::size_t budget = 1'000'000);
/// As above on a symbolic world (state `s`, names from `world`).
MissionReport check_mission(const Mission& m, const CompiledMission& cm, const symbolic::World& world,
                            const symbolic::State& s, std::size_t budget = 1'000'000);

}  // namespace quiver::agents
