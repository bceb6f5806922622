// A bash script embedded in the binary, written out and run.
#include "quiver/agents/runtime/process/embedded_script.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "quiver/agents/runtime/process/subprocess.h"

namespace quiver::agents::inline runtime {

int run_embedded_script(const std::string& who, const std::vector<std::pair<std::string, std::string_view>>& files,
                        const std::string& script, const std::vector<std::string>& args) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::string tmpl = (fs::temp_directory_path() / "quiver-script-XXXXXX").string();
  if (::mkdtemp(tmpl.data()) == nullptr) {
    std::fprintf(stderr, "%s: mkdtemp: %s\n", who.c_str(), std::strerror(errno));
    return 2;
  }
  const fs::path dir = tmpl;
  for (const auto& [name, text] : files) {
    std::ofstream f(dir / name, std::ios::binary);
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!f) {
      std::fprintf(stderr, "%s: cannot write %s\n", who.c_str(), (dir / name).c_str());
      fs::remove_all(dir, ec);
      return 2;
    }
  }
  std::vector<std::string> a = {"bash", (dir / script).string(), self_executable()};
  a.insert(a.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : a) argv.push_back(s.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  int status = 0;
  const int err = ::posix_spawnp(&pid, "bash", nullptr, nullptr, argv.data(), environ);
  if (err != 0)
    std::fprintf(stderr, "%s: cannot run bash: %s\n", who.c_str(), std::strerror(err));
  else
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
  fs::remove_all(dir, ec);
  if (err != 0) return 2;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 2;
}

}  // namespace quiver::agents::inline runtime
