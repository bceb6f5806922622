// libFuzzer: serialized CDR samples of the quiver_bye topic.
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, unsigned long size) {
  (void)quiver::fuzz::dds_sample(4, data, size);
  return 0;
}
