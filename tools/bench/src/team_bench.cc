// quiver bench team: writes the embedded script and its namespace library to a temporary
// directory and runs it with this executable's path.
#include "quiver/tools/bench/team_bench.h"
#include "quiver/tools/bench/bench_files.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

extern char** environ;

namespace quiver::tools::bench {

namespace {

std::string seconds_text(double s) {  // 10, 2.5: what bash passes on as it is
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

}  // namespace

int run_team_bench(const TeamBench& b) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) {
    std::fprintf(stderr, "quiver bench team: cannot find this executable: %s\n", ec.message().c_str());
    return 2;
  }
  std::string dir_template = (fs::temp_directory_path() / "quiver-bench-team-XXXXXX").string();
  if (::mkdtemp(dir_template.data()) == nullptr) {
    std::perror("quiver bench team: mkdtemp");
    return 2;
  }
  const fs::path dir = dir_template;
  for (const char* name : {"team_bench.sh", "netns.sh"}) {
    std::ofstream f(dir / name, std::ios::binary);
    const std::string_view text = embedded_file(name);
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!f) {
      std::fprintf(stderr, "quiver bench team: cannot write %s\n", (dir / name).c_str());
      fs::remove_all(dir, ec);
      return 2;
    }
  }
  std::vector<std::string> args = {"bash",
                                   (dir / "team_bench.sh").string(),
                                   exe.string(),
                                   "--robots",
                                   std::to_string(b.robots),
                                   "--seconds",
                                   seconds_text(b.seconds),
                                   "--nodes",
                                   std::to_string(b.nodes)};
  if (!b.out.empty()) args.insert(args.end(), {"--out", b.out});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  int status = 0;
  const int err = ::posix_spawnp(&pid, "bash", nullptr, nullptr, argv.data(), environ);
  if (err != 0) {
    std::fprintf(stderr, "quiver bench team: cannot run bash: %s\n", std::strerror(err));
  } else {
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
  }
  fs::remove_all(dir, ec);
  if (err != 0) return 2;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 2;
}

}  // namespace quiver::tools::bench
