// Which parser reads a text, and where include(...) files are found.

#include <filesystem>
#include <fstream>
#include <sstream>

#include "grammar_lexer.h"
#include "grammar_parsers.h"

namespace quiver::agents::inline rules {
namespace {

namespace fs = std::filesystem;

class Loader {
 public:
  explicit Loader(GrammarLoadOptions options) : opt_(std::move(options)) {}

  Result<Grammar> parse(std::string_view text, const std::string& source,
                        const std::string& base_dir) {
    if (!internal::looks_like_agm(text)) return internal::parse_quiver_grammar(text, source);
    internal::IncludeFn include;
    if (opt_.read_includes)
      include = [this, base_dir](const std::string& path, SourceLoc) {
        return read_include(path, base_dir);
      };
    return internal::parse_agm_grammar(text, source, include);
  }

  Result<Grammar> read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return make_error(ErrorCode::kIo, "load_grammar_file(): cannot open '" + path + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(path, ec);
    stack_.push_back(ec ? path : canonical.string());
    Result<Grammar> g = parse(ss.str(), path, fs::path(path).parent_path().string());
    stack_.pop_back();
    return g;
  }

 private:
  // AGM looks for an include in '/', '.' and its AGGLPATH. We look relative to the including
  // file, then in the include directories. AGM's files name absolute paths on their authors'
  // machines (/home/robocomp/...): a missing absolute path is looked for by its trailing
  // components (its last directory and file name at least), longest first, under the including
  // file's directory and its ancestors, then under the include directories.
  std::optional<fs::path> resolve(const std::string& path, const std::string& base_dir) const {
    std::error_code ec;
    auto exists = [&](const fs::path& p) { return fs::is_regular_file(p, ec); };
    const fs::path p(path);
    std::vector<fs::path> roots;
    roots.push_back(base_dir.empty() ? fs::path(".") : fs::path(base_dir));
    for (const std::string& d : opt_.include_dirs) roots.emplace_back(d);
    if (p.is_relative()) {
      for (const fs::path& r : roots)
        if (exists(r / p)) return r / p;
      return std::nullopt;
    }
    if (exists(p)) return p;
    std::vector<fs::path> parts;
    for (const fs::path& c : p.relative_path()) parts.push_back(c);
    std::vector<fs::path> ancestors;
    for (fs::path a = fs::absolute(roots.front(), ec); !a.empty(); a = a.parent_path()) {
      ancestors.push_back(a);
      if (a == a.parent_path()) break;
    }
    // At least the last directory and the file name: a bare file name could be another file.
    for (std::size_t i = 0; i + 2 <= parts.size(); ++i) {
      fs::path suffix;
      for (std::size_t k = i; k < parts.size(); ++k) suffix /= parts[k];
      for (const fs::path& a : ancestors)
        if (exists(a / suffix)) return a / suffix;
      for (std::size_t k = 1; k < roots.size(); ++k)
        if (exists(roots[k] / suffix)) return roots[k] / suffix;
    }
    return std::nullopt;
  }

  Result<Grammar> read_include(const std::string& path, const std::string& base_dir) {
    const auto found = resolve(path, base_dir);
    if (!found) {
      std::string where = "'" + (base_dir.empty() ? std::string(".") : base_dir) + "'";
      for (const std::string& d : opt_.include_dirs) where += ", '" + d + "'";
      return make_error(ErrorCode::kNotFound,
                        "include(" + path + "): no such file (looked under " + where +
                            (fs::path(path).is_absolute() ? " and their ancestors" : "") + ")");
    }
    std::error_code ec;
    const std::string canonical = fs::weakly_canonical(*found, ec).string();
    for (std::size_t i = 0; i < stack_.size(); ++i)
      if (stack_[i] == canonical) {
        std::string cycle;
        for (std::size_t k = i; k < stack_.size(); ++k) cycle += stack_[k] + " -> ";
        return make_error(ErrorCode::kMalformed,
                          "include(" + path + ") closes a cycle: " + cycle + canonical);
      }
    Result<Grammar> g = read_file(found->string());
    if (g.ok()) g->includes.insert(g->includes.begin(), found->string());
    return g;
  }

  GrammarLoadOptions opt_;
  std::vector<std::string> stack_;  // canonical paths of the files being read
};

}  // namespace

Result<Grammar> parse_grammar(std::string_view text, std::string_view source) {
  return parse_grammar(text, source, GrammarLoadOptions{});
}

Result<Grammar> parse_grammar(std::string_view text, std::string_view source,
                              const GrammarLoadOptions& options) {
  Loader loader(options);
  return loader.parse(text, std::string(source), options.base_dir);
}

Result<Grammar> load_grammar_file(const std::string& path, std::vector<std::string> include_dirs) {
  GrammarLoadOptions options;
  options.read_includes = true;
  options.include_dirs = std::move(include_dirs);
  Loader loader(std::move(options));
  return loader.read_file(path);
}

}  // namespace quiver::agents
