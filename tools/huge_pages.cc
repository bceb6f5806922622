// Agent processes run with glibc's malloc backing its heap with transparent huge pages.
#include "huge_pages.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

namespace quiver::tools {

void use_huge_pages(char** argv, bool here) {
  if (const char* off = std::getenv("QUIVER_HUGE_PAGES"); off != nullptr && std::strcmp(off, "0") == 0) return;
  const char* current = std::getenv("GLIBC_TUNABLES");
  std::string tunables = current != nullptr ? current : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos) return;  // said already (or done)
  tunables += (tunables.empty() ? "" : ":") + std::string("glibc.malloc.hugetlb=1");
  if (setenv("GLIBC_TUNABLES", tunables.c_str(), 1) != 0 || !here) return;
  execv("/proc/self/exe", argv);
  // Not executable after all: run on without (the tunable stays set for the programs it starts).
}

}  // namespace quiver::tools
