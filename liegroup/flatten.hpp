/// \file
/// LIEFLOW_FLATTEN: inline every call inside the function it marks (GCC's
/// and Clang's `flatten`), for the functions that integrate a flow in
/// ceres::Jet (the spring fits' shooting segments). In such long functions
/// Eigen's small kernels of the Jets' derivative vectors (copies, sums,
/// scaled sums) were left out of line and took 60 % of the universal spring
/// fit (perf); flattened, that fit runs 4.6 times faster. Optimized builds
/// only: in a Debug or AddressSanitizer build flattening these functions
/// took a compiler over 15 minutes per file, for no use.
#pragma once

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LIEFLOW_FLATTEN_UNDER_ASAN 1
#endif
#endif

/// LIEFLOW_NOT_FLATTENED: a function kept out of its callers (noinline),
/// its own calls flattened — for code that a flattened function calls but
/// must not take in (dynamics/joint_space/scalar_dynamics.hpp: GCC 12 failed
/// flattening the tree passes on Jets into the fits' residuals). The same
/// builds only; elsewhere nothing.
#if (defined(__GNUC__) || defined(__clang__)) && defined(NDEBUG) && !defined(__SANITIZE_ADDRESS__) && \
    !defined(LIEFLOW_FLATTEN_UNDER_ASAN)
#define LIEFLOW_FLATTEN __attribute__((flatten))
#define LIEFLOW_NOT_FLATTENED __attribute__((noinline, flatten))
#else
#define LIEFLOW_FLATTEN
#define LIEFLOW_NOT_FLATTENED
#endif
