/// \file
/// The timed operations shared by measureSpeed (std::chrono) and
/// bench_liegroup (Google Benchmark): the input arrays, one struct per
/// operation with `static R run(const SpeedInputs&, std::size_t i)`, and the
/// pairing of each lieflow operation with its Eigen baseline.
///
/// Baselines (exactly what is timed):
///   AngleAxis->Quaternion : θ = w.norm(); Quaterniond(AngleAxisd(θ, w / θ))
///   Quaternion->AngleAxis : AngleAxisd aa(q); aa.angle() * aa.axis()
///   quaternion product    : qa * qb
///   quaternion*vector     : q * p   (Eigen's _transformVector)
///   quaternion conjugate  : q.conjugate()
///   AngleAxis->matrix     : θ = w.norm(); AngleAxisd(θ, w / θ).toRotationMatrix()
/// The baseline of an operation sees the same rotations as the operation: the
/// rotation vectors of SE3 exp are those of SO3 exp, the rotations of the SE(3)
/// elements are those of the SO(3) elements.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "liegroup_measure/liegroup_measure.hpp"
#include "liegroup/se3.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace measure {

/// std::allocator with every array starting on a 64-byte cache line, so that
/// an operation and its baseline see the same alignment of their inputs (with
/// the default 16-byte alignment, whether 32-byte quaternions straddle cache
/// lines depends on where the heap put each array: up to 1.5× on the cheapest
/// operations).
template <typename T>
struct CacheLineAllocator {
  using value_type = T;
  static constexpr std::size_t kAlignment = 64;
  CacheLineAllocator() = default;
  template <typename U>
  CacheLineAllocator(const CacheLineAllocator<U>&) {}
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(kAlignment)));
  }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(kAlignment)); }
  template <typename U>
  bool operator==(const CacheLineAllocator<U>&) const { return true; }
  template <typename U>
  bool operator!=(const CacheLineAllocator<U>&) const { return false; }
};

template <typename T>
using AlignedVector = std::vector<T, CacheLineAllocator<T>>;

/// Pre-generated random inputs, cycled through with index i & mask.
struct SpeedInputs {
  /// A power of two: 1024 elements, so one operation's inputs (≤ 64 KiB) stay
  /// in L2 and the cycle is too long for the branch predictor to learn the
  /// branch pattern of lieflow's series/closed-form switches.
  static constexpr std::size_t kSize = 1024;
  static constexpr std::size_t kMask = kSize - 1;
  /// The seed both harnesses use, so that they time the same elements.
  static constexpr std::uint64_t kDefaultSeed = 0x5eed'11ef'f10eULL;

  AlignedVector<Eigen::Vector3d> w;  ///< rotation vectors: uniform axis, θ uniform in (0, π)
  AlignedVector<Eigen::Matrix<double, 6, 1>> xi;  ///< (ρ, w[i]), ρ uniform in [−1, 1]³
  AlignedVector<SO3d> a, b;                  ///< Haar-uniform rotations
  AlignedVector<Eigen::Quaterniond> qa, qb;  ///< the same rotations as Eigen quaternions
  AlignedVector<SE3d> A, B;                  ///< (a[i], t), (b[i], t'), t uniform in [−1, 1]³
  AlignedVector<Eigen::Vector3d> p;          ///< points uniform in [−1, 1]³

  explicit SpeedInputs(std::uint64_t seed) {
    std::mt19937_64 gen(seed);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::uniform_real_distribution<double> cube(-1.0, 1.0);
    const double pi = 3.14159265358979323846;
    for (std::size_t i = 0; i < kSize; ++i) {
      Eigen::Vector3d axis;
      do {
        axis = Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
      } while (axis.norm() < 1e-6);
      double theta;
      do {
        theta = pi * unit(gen);
      } while (theta <= 0.0);
      w.push_back(theta * axis.normalized());
      Eigen::Matrix<double, 6, 1> x;
      x << cube(gen), cube(gen), cube(gen), w.back();
      xi.push_back(x);
      a.push_back(SO3d::random(gen));
      b.push_back(SO3d::random(gen));
      qa.push_back(a.back().quaternion());
      qb.push_back(b.back().quaternion());
      A.emplace_back(a.back(), Eigen::Vector3d(cube(gen), cube(gen), cube(gen)));
      B.emplace_back(b.back(), Eigen::Vector3d(cube(gen), cube(gen), cube(gen)));
      p.emplace_back(cube(gen), cube(gen), cube(gen));
    }
  }
};

namespace cases {

// ---- lieflow operations ------------------------------------------------------

struct SO3Exp {
  static SO3d run(const SpeedInputs& in, std::size_t i) { return SO3d::exp(in.w[i]); }
};
struct SO3Log {
  static Eigen::Vector3d run(const SpeedInputs& in, std::size_t i) { return in.a[i].log(); }
};
struct SO3Compose {
  static SO3d run(const SpeedInputs& in, std::size_t i) { return in.a[i] * in.b[i]; }
};
struct SO3Act {
  static Eigen::Vector3d run(const SpeedInputs& in, std::size_t i) { return in.a[i] * in.p[i]; }
};
struct SO3Inverse {
  static SO3d run(const SpeedInputs& in, std::size_t i) { return in.a[i].inverse(); }
};
struct SO3Jr {
  static Eigen::Matrix3d run(const SpeedInputs& in, std::size_t i) { return SO3d::Jr(in.w[i]); }
};
struct SO3JrInv {
  static Eigen::Matrix3d run(const SpeedInputs& in, std::size_t i) { return SO3d::JrInv(in.w[i]); }
};
struct SE3Exp {
  static SE3d run(const SpeedInputs& in, std::size_t i) { return SE3d::exp(in.xi[i]); }
};
struct SE3Log {
  static Eigen::Matrix<double, 6, 1> run(const SpeedInputs& in, std::size_t i) {
    return in.A[i].log();
  }
};
struct SE3Compose {
  static SE3d run(const SpeedInputs& in, std::size_t i) { return in.A[i] * in.B[i]; }
};
struct SE3Act {
  static Eigen::Vector3d run(const SpeedInputs& in, std::size_t i) { return in.A[i] * in.p[i]; }
};

// ---- Eigen baselines -----------------------------------------------------------

struct EigenAngleAxisToQuaternion {
  static Eigen::Quaterniond run(const SpeedInputs& in, std::size_t i) {
    const Eigen::Vector3d& w = in.w[i];
    const double theta = w.norm();
    return Eigen::Quaterniond(Eigen::AngleAxisd(theta, w / theta));
  }
};
struct EigenQuaternionToAngleAxis {
  static Eigen::Vector3d run(const SpeedInputs& in, std::size_t i) {
    const Eigen::AngleAxisd aa(in.qa[i]);
    return aa.angle() * aa.axis();
  }
};
struct EigenQuaternionProduct {
  static Eigen::Quaterniond run(const SpeedInputs& in, std::size_t i) { return in.qa[i] * in.qb[i]; }
};
struct EigenQuaternionVector {
  static Eigen::Vector3d run(const SpeedInputs& in, std::size_t i) { return in.qa[i] * in.p[i]; }
};
struct EigenQuaternionConjugate {
  static Eigen::Quaterniond run(const SpeedInputs& in, std::size_t i) { return in.qa[i].conjugate(); }
};
struct EigenAngleAxisToMatrix {
  static Eigen::Matrix3d run(const SpeedInputs& in, std::size_t i) {
    const Eigen::Vector3d& w = in.w[i];
    const double theta = w.norm();
    return Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
  }
};

}  // namespace cases

/// Calls f(LieflowCase{}, BaselineCase{}, target) for every entry of
/// speedTargets(), in order (the k-th call gets speedTargets()[k]).
template <typename F>
void forEachSpeedPair(F&& f) {
  using namespace cases;
  const std::vector<SpeedTarget>& t = speedTargets();
  f(SO3Exp{}, EigenAngleAxisToQuaternion{}, t.at(0));
  f(SO3Log{}, EigenQuaternionToAngleAxis{}, t.at(1));
  f(SO3Compose{}, EigenQuaternionProduct{}, t.at(2));
  f(SO3Act{}, EigenQuaternionVector{}, t.at(3));
  f(SO3Inverse{}, EigenQuaternionConjugate{}, t.at(4));
  f(SO3Jr{}, EigenAngleAxisToMatrix{}, t.at(5));
  f(SO3JrInv{}, EigenAngleAxisToMatrix{}, t.at(6));
  f(SE3Exp{}, EigenAngleAxisToQuaternion{}, t.at(7));
  f(SE3Log{}, EigenQuaternionToAngleAxis{}, t.at(8));
  f(SE3Compose{}, EigenQuaternionProduct{}, t.at(9));
  f(SE3Act{}, EigenQuaternionVector{}, t.at(10));
}

}  // namespace measure
}  // namespace lieflow
