/// \file
/// A counting replacement of the global operator new and, with glibc, of
/// malloc and its family, for the programs that check "no heap allocation per
/// step":
/// bench_step_allocations and lieflow_allocation_tests. Include it in exactly
/// one translation unit of an executable (it defines the replaceable
/// allocation functions); not under AddressSanitizer, whose own replacement
/// it would take the place of. allocationCount() is the number of heap
/// allocations so far (operator new, Eigen's and C libraries' malloc).
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

// GCC 12's -Wmismatched-new-delete does not know that these are the
// replacements and flags their free().
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

namespace lieflow {
namespace bench {
inline std::atomic<long> g_allocations{0};
inline long allocationCount() { return g_allocations.load(); }
}  // namespace bench
}  // namespace lieflow

#if defined(__GLIBC__)
// glibc: malloc and its family are replaced too (forwarding to glibc's own
// __libc_* entry points), so that Eigen's dynamic matrices (aligned_malloc →
// malloc) and C libraries (KLU) are counted with operator new, which goes
// through malloc. Each call counts once.
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void __libc_free(void*);
void* __libc_memalign(std::size_t, std::size_t);

void* malloc(std::size_t n) noexcept {
  ++lieflow::bench::g_allocations;
  return __libc_malloc(n);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  ++lieflow::bench::g_allocations;
  return __libc_calloc(count, size);
}
void* realloc(void* p, std::size_t n) noexcept {
  ++lieflow::bench::g_allocations;
  return __libc_realloc(p, n);
}
void free(void* p) noexcept { __libc_free(p); }
void* memalign(std::size_t alignment, std::size_t n) noexcept {
  ++lieflow::bench::g_allocations;
  return __libc_memalign(alignment, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) noexcept {
  ++lieflow::bench::g_allocations;
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) noexcept {
  ++lieflow::bench::g_allocations;
  *out = __libc_memalign(alignment, n);
  return *out ? 0 : 12;  // ENOMEM
}
}
#define LIEFLOW_COUNT_IN_OPERATOR_NEW 0
#else
#define LIEFLOW_COUNT_IN_OPERATOR_NEW 1
#endif

void* operator new(std::size_t n) {
  if (LIEFLOW_COUNT_IN_OPERATOR_NEW) ++lieflow::bench::g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (LIEFLOW_COUNT_IN_OPERATOR_NEW) ++lieflow::bench::g_allocations;
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  if (LIEFLOW_COUNT_IN_OPERATOR_NEW) ++lieflow::bench::g_allocations;
  return std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
