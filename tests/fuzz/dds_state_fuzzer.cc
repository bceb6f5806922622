// libFuzzer: serialized CDR samples of the quiver_state topic.
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, unsigned long size) {
  (void)quiver::fuzz::dds_sample(3, data, size);
  return 0;
}
