#pragma once

#include <Eigen/Dense>
#include <array>
#include <complex>
#include <cstddef>

#include "mimpact/numerics/mindlin_play.hpp"

// A Mindlin spring in space over one step of an integration that does not stop at its switches:
// the planar play's counterpart (mindlin_play.hpp) for the moving geometry's groups in space
// (docs/design/moving_geometry.md, "Friction within a step"). The stretch xi is a vector in the
// contact's tangent plane, which turns with the normal n:
//   stick: xi = P(n) (xi_0 + int s dt), P(n) the projection on the plane;
//   slip:  xi = r_c d, r_c = c delta, the direction d turning toward the slip's,
//          d' = (s - (d.s) d) / r_c (mindlin_spring.hpp), at a rate |s| / r_c that grows
//          without bound toward the spring's birth, where r_c = 0.
// In a frame (e1, e2) of the plane, d = e^{i theta} solves the Riccati equation
//   w' = (z - conj(z) w^2) / (2 r_c),   z = s.e1 + i s.e2,
// linear in homogeneous coordinates w = u / v: (u, v)' = [[0, a], [conj(a), 0]] (u, v) with
// a = z / (2 r_c). Its flow is integrated by Magnus's sixth-order exponential (Blanes, Casas &
// Ros, BIT 40, 2000; Blanes, Casas, Oteo & Ros, Phys. Rep. 470, 2009) over equal pieces of
// the step's rest, as many as its turning and the tolerance ask, at most kDirectionPieces: where
// the slip's direction is fixed it reduces to the quadrature of |s| / r_c in the closed form
// tan(phi/2) = tan(phi_0/2) exp(-int |s| / r_c dt); it keeps |w| = 1 (the matrices are in su(1,1))
// and is stable however stiff the turning.
namespace mimpact::numerics::mindlin {

inline constexpr std::size_t kDirectionPieces = 32;

// The direction of a slip at a share of its step, in its segment's frame: w = e^{i theta}.
struct DirectionNode {
  double at = 0.0;
  std::complex<double> w;
};

// A spring's state between two switches of its step.
struct SpatialSegment {
  double from = 0.0, to = 0.0;  // shares of the step
  Regime regime = Regime::open;
  // stick: the stretch (m) at `from`; slip: e1, the direction at `from`
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d across = Eigen::Vector3d::Zero();  // slip: e2 = n x e1 at `from`
  std::size_t first_node = 0, nodes = 0;             // slip: its direction's, in the play's
};

// The spring's stretch over a step: its segments from s = 0 to the share `until`.
class SpatialPlay {
 public:
  using Curve = std::array<StepPolynomial, 3>;  // a vector's x, y and z
  // The contact along the step: the slip times the step (m, the stretch's rate in s while it
  // sticks), tangent to the normal (not necessarily of length 1), and the overlap (m).
  struct Contact {
    Curve slip, normal;
    StepPolynomial overlap;
  };

  // `cap_ratio` c = mu / (lambda eta) (mindlin::terms); `stretch` (m) the stretch at s = 0,
  // taken into the tangent plane and within the cap there; a slip's direction to within
  // `turn_tolerance` (rad).
  SpatialPlay(const Contact& contact, double cap_ratio, const Eigen::Vector3d& stretch,
              double turn_tolerance, double until = 1.0);

  Eigen::Vector3d stretch_at(const SpatialSegment& segment, double s) const;  // m, s within it
  Eigen::Vector3d final_stretch() const { return stretch_at(segments_[count_ - 1], until_); }
  const SpatialSegment* begin() const { return segments_.data(); }
  const SpatialSegment* end() const { return segments_.data() + count_; }
  std::size_t switches() const { return count_ - 1; }

  // Gauss-Legendre nodes on each loaded segment: visit(s, weight, stretch) with the weights
  // summing to the segment's length.
  template <class Visit>
  void quadrature(Visit&& visit) const;

 private:
  static constexpr std::size_t kMostSegments = 12;  // the rest of the step keeps the last
  static constexpr std::size_t kMostNodes = kMostSegments * (kDirectionPieces + 1);
  static Eigen::Vector3d value(const Curve& curve, double s);
  Eigen::Vector3d unit_normal(double s) const { return value(normal_, s).normalized(); }
  // the slip in a slip segment's frame
  std::complex<double> in_frame(const SpatialSegment& segment, double s) const;
  // w at `to` from w at `from` within a slip segment: one Magnus step
  std::complex<double> turned(const SpatialSegment& segment, std::complex<double> w, double from,
                              double to) const;
  std::complex<double> direction_at(const SpatialSegment& segment, double s) const;
  // the equal pieces a slip's direction is integrated over, to until_
  std::size_t pieces_for(const SpatialSegment& segment) const;
  // a slip begun at `at` in the direction `toward` (in the tangent plane there), its direction
  // integrated to until_ into nodes_
  SpatialSegment slip_from(double at, const Eigen::Vector3d& toward);
  void add_node(double at, std::complex<double> w);
  void start(const Eigen::Vector3d& stretch);
  // > 0 within the segment, crossing 0 at its first switch (a segment ends there, or at
  // until_)
  double watched(const SpatialSegment& segment, double s) const;
  SpatialSegment after(const SpatialSegment& ended, double at);

  Curve slip_, normal_, slip_integral_;
  StepPolynomial overlap_, overlap_rate_;
  double cap_ratio_ = 0.0, until_ = 1.0;
  double pieces_per_turn_ = 1.0;  // (pieces_for)
  std::array<SpatialSegment, kMostSegments> segments_{};
  std::size_t count_ = 0;
  std::array<DirectionNode, kMostNodes> nodes_;
  std::size_t node_count_ = 0;
};

template <class Visit>
void SpatialPlay::quadrature(Visit&& visit) const {
  for (const SpatialSegment& segment : *this) {
    if (segment.regime == Regime::open || !(segment.to > segment.from)) continue;
    play_detail::gauss_legendre(segment.from, segment.to, [&](double s, double weight) {
      visit(s, weight, stretch_at(segment, s));
    });
  }
}

}  // namespace mimpact::numerics::mindlin
