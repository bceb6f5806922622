// A world file of any kind, loaded by the loader its content calls for.
#include "quiver/interop/any_world.h"

#include "quiver/graph/world_file.h"
#include "quiver/interop/agm.h"
#include "quiver/interop/dsr.h"
#include "quiver/interop/interop.h"

namespace quiver::interop {

Status load_any_world(graph::Graph& g, std::string_view text, const std::string& source) {
  const WorldFormat f = detect_format(text);
  switch (f) {
    case WorldFormat::kQuiverJson: {
      auto r = graph::load_world(g, text, source);
      return r.ok() ? Status{} : Status(r.error());
    }
    case WorldFormat::kDsrJson: {
      auto r = import_dsr(g, text, source);
      return r.ok() ? Status{} : Status(r.error());
    }
    case WorldFormat::kAgmXml: {
      auto r = import_agm(g, text, source);
      return r.ok() ? Status{} : Status(r.error());
    }
    default:
      return make_error(ErrorCode::kMalformed, source + " is " + to_string(f) +
                                                   ", not a world (Quiver JSON, CORTEX DSR JSON or AGM XML)");
  }
}

Status load_any_world_file(graph::Graph& g, const std::string& path) {
  auto text = read_file("load_any_world_file", path);
  if (!text.ok()) return text.error();
  return load_any_world(g, *text, path);
}

}  // namespace quiver::interop
