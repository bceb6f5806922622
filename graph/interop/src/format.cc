// Format detection and file I/O shared by the converters.

#include <cerrno>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "quiver/interop/interop.h"

namespace quiver::interop {

const char* to_string(WorldFormat f) {
  switch (f) {
    case WorldFormat::kQuiverJson: return "a Quiver world file";
    case WorldFormat::kDsrJson: return "a CORTEX DSR JSON world";
    case WorldFormat::kAgmXml: return "an AGM XML world";
    case WorldFormat::kOtherJson: return "JSON";
    case WorldFormat::kOtherXml: return "XML";
    case WorldFormat::kUnknown: break;
  }
  return "neither JSON nor XML";
}

namespace {

std::string_view skip_space(std::string_view t) {
  if (t.substr(0, 3) == "\xEF\xBB\xBF") t.remove_prefix(3);
  while (!t.empty() && (t[0] == ' ' || t[0] == '\t' || t[0] == '\r' || t[0] == '\n')) t.remove_prefix(1);
  return t;
}

// The name of the first element, past the XML declaration, comments, processing instructions
// and a DOCTYPE; empty if there is none.
std::string xml_root(std::string_view t) {
  while (true) {
    t = skip_space(t);
    if (t.substr(0, 4) == "<!--") {
      auto end = t.find("-->", 4);
      if (end == std::string_view::npos) return "";
      t.remove_prefix(end + 3);
    } else if (t.substr(0, 2) == "<?") {
      auto end = t.find("?>", 2);
      if (end == std::string_view::npos) return "";
      t.remove_prefix(end + 2);
    } else if (t.substr(0, 2) == "<!") {
      auto end = t.find('>', 2);
      if (end == std::string_view::npos) return "";
      t.remove_prefix(end + 1);
    } else {
      break;
    }
  }
  if (t.empty() || t[0] != '<') return "";
  std::size_t i = 1;
  while (i < t.size() && t[i] != '>' && t[i] != '/' && t[i] != ' ' && t[i] != '\t' && t[i] != '\r' && t[i] != '\n') ++i;
  return std::string(t.substr(1, i - 1));
}

}  // namespace

WorldFormat detect_format(std::string_view text, std::string* root) {
  const std::string_view t = skip_space(text);
  if (t.empty()) return WorldFormat::kUnknown;
  if (t[0] == '<') {
    std::string name = xml_root(t);
    if (root) *root = name;
    return name == "AGMModel" ? WorldFormat::kAgmXml : WorldFormat::kOtherXml;
  }
  if (t[0] != '{' && t[0] != '[') return WorldFormat::kUnknown;
  nlohmann::json j = nlohmann::json::parse(t, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) return WorldFormat::kOtherJson;
  if (j.contains("DSRModel")) return WorldFormat::kDsrJson;
  if (j.contains("quiver_world")) return WorldFormat::kQuiverJson;
  return WorldFormat::kOtherJson;
}

Result<std::string> read_file(const char* fn, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kIo, std::string(fn) + ": cannot open '" + path + "': " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return make_error(ErrorCode::kIo, std::string(fn) + ": reading '" + path + "' failed");
  return ss.str();
}

Status write_file(const char* fn, const std::string& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return make_error(ErrorCode::kIo, std::string(fn) + ": cannot write '" + path + "': " + std::strerror(errno));
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) return make_error(ErrorCode::kIo, std::string(fn) + ": writing '" + path + "' failed");
  return {};
}

}  // namespace quiver::interop
