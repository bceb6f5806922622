#pragma once
// Counting heap allocations in a test executable, as Drake's LimitMalloc does: this header
// replaces malloc and its relatives for the whole process (include it in exactly one source file
// of an executable), and CountAllocations counts the calls one thread makes while it lives.
// Everything C++ allocates (operator new, the containers) goes through malloc.

#include <cstddef>
#include <cstdlib>

extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void* __libc_memalign(std::size_t, std::size_t);

namespace quiver::test_alloc {
inline thread_local long t_allocations = 0;  // this thread's calls, counted while t_counting
inline thread_local bool t_counting = false;
inline void count_allocation() {
  if (t_counting) ++t_allocations;
}
}  // namespace quiver::test_alloc

extern "C" {
void* malloc(std::size_t n) {
  quiver::test_alloc::count_allocation();
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t size) {
  quiver::test_alloc::count_allocation();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t n) {
  quiver::test_alloc::count_allocation();
  return __libc_realloc(p, n);
}
void* memalign(std::size_t alignment, std::size_t n) {
  quiver::test_alloc::count_allocation();
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  quiver::test_alloc::count_allocation();
  *out = __libc_memalign(alignment, n);
  return *out != nullptr ? 0 : 12;  // ENOMEM
}
void* aligned_alloc(std::size_t alignment, std::size_t n) {
  quiver::test_alloc::count_allocation();
  return __libc_memalign(alignment, n);
}
}

namespace quiver::test_alloc {

/// Counts the allocations this thread makes while it lives.
class CountAllocations {
 public:
  CountAllocations() {
    t_allocations = 0;
    t_counting = true;
  }
  ~CountAllocations() { t_counting = false; }
  long count() const { return t_allocations; }
};

}  // namespace quiver::test_alloc
