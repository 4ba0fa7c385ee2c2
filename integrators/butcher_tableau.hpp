/// \file
/// Explicit Butcher tableaux (Hairer, Nørsett, Wanner, "Solving ODEs I",
/// §II.1 and §II.4) for the Runge–Kutta–Munthe-Kaas stepper, with the order
/// each one has and, for embedded pairs, the order of the error estimate.
#pragma once

#include <array>
#include <string>

namespace lieflow {

/// An explicit s-stage tableau (s ≤ kMaxStages): c, A strictly lower
/// triangular, weights b and, for an embedded pair, the weights b̂ of the
/// companion solution.
struct ButcherTableau {
  static constexpr int kMaxStages = 7;
  std::string name;
  int stages = 0;
  int order = 0;
  /// Order of the embedded solution (0: no embedded pair).
  int embedded_order = 0;
  /// The solution advanced is the higher-order one (local extrapolation).
  std::array<double, kMaxStages> c{};
  std::array<std::array<double, kMaxStages>, kMaxStages> a{};
  std::array<double, kMaxStages> b{};
  std::array<double, kMaxStages> b_embedded{};
  /// First-same-as-last: the last stage is f at the new point.
  bool fsal = false;
  /// Continuous extension of an FSAL pair in the form of Hairer's DOPRI5
  /// (Hairer, Nørsett & Wanner I, §II.6, eq. (6.12) and the code's CONTD5):
  /// with Δ = h Σ bᵢKᵢ, s = 1 − θ,
  ///   u(θ) = θ(Δ + s(hK₁ − Δ + θ(2Δ − h(K₁ + K_last) + s·h Σ dᵢKᵢ))),
  /// which matches u(0) = 0, u'(0) = hK₁, u(1) = Δ, u'(1) = hK_last and is
  /// of order 4 for Dormand–Prince (`dense_order`, 0: no dense output).
  int dense_order = 0;
  std::array<double, kMaxStages> dense_d{};

  bool hasEmbedded() const { return embedded_order > 0; }
  bool hasDenseOutput() const { return dense_order > 0; }

  /// Forward Euler, order 1.
  static ButcherTableau euler();
  /// Heun's method (explicit trapezoid), order 2.
  static ButcherTableau heun();
  /// Kutta's third-order method.
  static ButcherTableau kutta3();
  /// The classical fourth-order Runge–Kutta method.
  static ButcherTableau rk4();
  /// Bogacki–Shampine 3(2), FSAL.
  static ButcherTableau bogackiShampine32();
  /// Dormand–Prince 5(4), FSAL (the pair of ode45).
  static ButcherTableau dormandPrince54();
  /// Butcher's seven-stage method of order 6 (Butcher 1964, "On Runge–Kutta
  /// processes of high order", J. Austral. Math. Soc. 4; Hairer, Nørsett &
  /// Wanner I, §II.5: six stages cannot reach order 6, so seven is the least).
  static ButcherTableau butcher6();
};

inline ButcherTableau ButcherTableau::euler() {
  ButcherTableau t;
  t.name = "euler";
  t.stages = 1;
  t.order = 1;
  t.b[0] = 1.0;
  return t;
}

inline ButcherTableau ButcherTableau::heun() {
  ButcherTableau t;
  t.name = "heun";
  t.stages = 2;
  t.order = 2;
  t.c = {0.0, 1.0};
  t.a[1][0] = 1.0;
  t.b = {0.5, 0.5};
  return t;
}

inline ButcherTableau ButcherTableau::kutta3() {
  ButcherTableau t;
  t.name = "kutta3";
  t.stages = 3;
  t.order = 3;
  t.c = {0.0, 0.5, 1.0};
  t.a[1][0] = 0.5;
  t.a[2][0] = -1.0;
  t.a[2][1] = 2.0;
  t.b = {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0};
  return t;
}

inline ButcherTableau ButcherTableau::rk4() {
  ButcherTableau t;
  t.name = "rk4";
  t.stages = 4;
  t.order = 4;
  t.c = {0.0, 0.5, 0.5, 1.0};
  t.a[1][0] = 0.5;
  t.a[2][1] = 0.5;
  t.a[3][2] = 1.0;
  t.b = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};
  return t;
}

inline ButcherTableau ButcherTableau::bogackiShampine32() {
  ButcherTableau t;
  t.name = "bogacki-shampine-3(2)";
  t.stages = 4;
  t.order = 3;
  t.embedded_order = 2;
  t.fsal = true;
  t.c = {0.0, 0.5, 0.75, 1.0};
  t.a[1][0] = 0.5;
  t.a[2][1] = 0.75;
  t.a[3][0] = 2.0 / 9.0;
  t.a[3][1] = 1.0 / 3.0;
  t.a[3][2] = 4.0 / 9.0;
  t.b = {2.0 / 9.0, 1.0 / 3.0, 4.0 / 9.0, 0.0};
  t.b_embedded = {7.0 / 24.0, 1.0 / 4.0, 1.0 / 3.0, 1.0 / 8.0};
  return t;
}

inline ButcherTableau ButcherTableau::dormandPrince54() {
  ButcherTableau t;
  t.name = "dormand-prince-5(4)";
  t.stages = 7;
  t.order = 5;
  t.embedded_order = 4;
  t.fsal = true;
  t.c = {0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0};
  t.a[1] = {1.0 / 5.0};
  t.a[2] = {3.0 / 40.0, 9.0 / 40.0};
  t.a[3] = {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0};
  t.a[4] = {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0};
  t.a[5] = {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0};
  t.a[6] = {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0};
  t.b = {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0};
  t.b_embedded = {5179.0 / 57600.0, 0.0,          7571.0 / 16695.0, 393.0 / 640.0,
                  -92097.0 / 339200.0, 187.0 / 2100.0, 1.0 / 40.0};
  // Shampine's order-4 continuous extension, coefficients as in DOPRI5.
  t.dense_order = 4;
  t.dense_d = {-12715105075.0 / 11282082432.0, 0.0, 87487479700.0 / 32700410799.0,
               -10690763975.0 / 1880347072.0, 701980252875.0 / 199316789632.0,
               -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0};
  return t;
}

/// c = (0, 1/3, 2/3, 1/3, 1/2, 1/2, 1), b = (11, 0, 81, 81, −32, −32, 11)/120;
/// its order is measured (tests/integrators/convergence_test.cpp: slope 6 in
/// the orientation and the rates of a torqued top on SO(3)).
inline ButcherTableau ButcherTableau::butcher6() {
  ButcherTableau t;
  t.name = "butcher6";
  t.stages = 7;
  t.order = 6;
  t.c = {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0, 1.0 / 2.0, 1.0 / 2.0, 1.0};
  t.a[1] = {1.0 / 3.0};
  t.a[2] = {0.0, 2.0 / 3.0};
  t.a[3] = {1.0 / 12.0, 1.0 / 3.0, -1.0 / 12.0};
  t.a[4] = {-1.0 / 16.0, 9.0 / 8.0, -3.0 / 16.0, -3.0 / 8.0};
  t.a[5] = {0.0, 9.0 / 8.0, -3.0 / 8.0, -3.0 / 4.0, 1.0 / 2.0};
  t.a[6] = {9.0 / 44.0, -9.0 / 11.0, 63.0 / 44.0, 18.0 / 11.0, 0.0, -16.0 / 11.0};
  t.b = {11.0 / 120.0, 0.0, 27.0 / 40.0, 27.0 / 40.0, -4.0 / 15.0, -4.0 / 15.0, 11.0 / 120.0};
  return t;
}

}  // namespace lieflow
