// libFuzzer entry point (built with -DQUIVER_BUILD_FUZZERS=ON and clang).
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, unsigned long size) {
  (void)quiver::fuzz::schema_file(data, size);
  return 0;
}
