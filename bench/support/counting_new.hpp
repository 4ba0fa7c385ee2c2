/// \file
/// A counting replacement of the global operator new (malloc/free underneath),
/// for the programs that check "no heap allocation per step":
/// bench_step_allocations and lieflow_allocation_tests. Include it in exactly
/// one translation unit of an executable (it defines the replaceable
/// allocation functions); not under AddressSanitizer, whose own replacement
/// it would take the place of. allocationCount() is the number of operator
/// new calls so far.
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
inline std::atomic<long> g_operator_new_calls{0};
inline long allocationCount() { return g_operator_new_calls.load(); }
}  // namespace bench
}  // namespace lieflow

void* operator new(std::size_t n) {
  ++lieflow::bench::g_operator_new_calls;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  ++lieflow::bench::g_operator_new_calls;
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  ++lieflow::bench::g_operator_new_calls;
  return std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
