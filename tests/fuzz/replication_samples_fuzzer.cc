// libFuzzer: a stream of serialized CDR samples fed to a replicator (fuzz_targets.h).
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, unsigned long size) {
  (void)quiver::fuzz::replication_samples(data, size);
  return 0;
}
