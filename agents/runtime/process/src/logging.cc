// The one logger setup of Quiver's programs: named spdlog loggers on stderr, and one level for them all.
#include "quiver/agents/runtime/process/logging.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace quiver::agents::inline runtime {

std::shared_ptr<spdlog::logger> named_logger(const std::string& name) {
  if (auto existing = spdlog::get(name)) return existing;
  auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>(spdlog::color_mode::never);
  auto logger = std::make_shared<spdlog::logger>(name, sink);
  logger->set_pattern("%H:%M:%S.%e [%n] %l: %v");
  logger->set_level(spdlog::get_level());
  spdlog::register_logger(logger);
  return logger;
}

bool set_log_level(std::string_view level) {
  const spdlog::level::level_enum l = spdlog::level::from_str(std::string(level));
  // from_str answers "off" for any word it does not know.
  if (l == spdlog::level::off && level != "off") return false;
  spdlog::set_level(l);  // every registered logger, and the default for new ones
  return true;
}

}  // namespace quiver::agents
