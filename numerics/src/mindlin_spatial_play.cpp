#include "mimpact/numerics/mindlin_spatial_play.hpp"

#include <algorithm>
#include <cmath>

namespace mimpact::numerics::mindlin {

namespace {

constexpr double kOnTheCap = 1e-9;  // relative: a stretch this near the cap starts on it
// A Magnus step's error on a piece over which the direction turns at |s| / r_c grows as
// (h |s| / r_c)^7, kTurnError times it (measured on tests/numerics/test_mindlin_spatial_play.cpp's
// turning slip): N pieces over a span that turns by at most T take the direction to within e
// where N >= (kTurnError / e)^(1/6) T^(7/6).
constexpr double kTurnError = 3.75e-6;

// [[i r, b], [conj(b), -i r]] of su(1,1), r real: the Riccati equation's matrices and their
// brackets
struct Su11 {
  double r = 0.0;
  std::complex<double> b;
};
Su11 operator+(const Su11& x, const Su11& y) { return {x.r + y.r, x.b + y.b}; }
Su11 operator-(const Su11& x, const Su11& y) { return {x.r - y.r, x.b - y.b}; }
Su11 operator*(double c, const Su11& x) { return {c * x.r, c * x.b}; }
// [x, y] = x y - y x
Su11 bracket(const Su11& x, const Su11& y) {
  return {2.0 * std::imag(x.b * std::conj(y.b)),
          std::complex<double>(0.0, 2.0) * (x.r * y.b - y.r * x.b)};
}

Eigen::Vector3d on_plane(const Eigen::Vector3d& v, const Eigen::Vector3d& unit_normal) {
  return v - v.dot(unit_normal) * unit_normal;
}

}  // namespace

SpatialPlay::SpatialPlay(const Contact& contact, double cap_ratio, const Eigen::Vector3d& stretch,
                         double turn_tolerance, double until)
    : slip_(contact.slip),
      normal_(contact.normal),
      overlap_(contact.overlap),
      overlap_rate_(contact.overlap.derivative()),
      cap_ratio_(cap_ratio),
      until_(until),
      pieces_per_turn_(std::pow(kTurnError / turn_tolerance, 1.0 / 6.0)) {
  for (std::size_t k = 0; k < 3; ++k) slip_integral_[k] = contact.slip[k].antiderivative();
  start(stretch);
  count_ = play_detail::split_step(
      segments_, until_,
      [this](const SpatialSegment& segment, double s) { return watched(segment, s); },
      [this](const SpatialSegment& ended, double at) { return after(ended, at); });
}

Eigen::Vector3d SpatialPlay::value(const Curve& curve, double s) {
  return {curve[0](s), curve[1](s), curve[2](s)};
}

std::complex<double> SpatialPlay::in_frame(const SpatialSegment& segment, double s) const {
  const Eigen::Vector3d slip = value(slip_, s);
  return {slip.dot(segment.start), slip.dot(segment.across)};
}

std::complex<double> SpatialPlay::turned(const SpatialSegment& segment, std::complex<double> w,
                                         double from, double to) const {
  const double h = to - from, middle = 0.5 * (from + to), offset = h * std::sqrt(15.0) / 10.0;
  // A at the three Gauss-Legendre nodes, times h: (0, a) in su(1,1)
  std::array<Su11, 3> a;
  for (std::size_t k = 0; k < 3; ++k) {
    const double s = middle + (double(k) - 1.0) * offset, delta = overlap_(s);
    if (!(delta > 0.0) || !(h > 0.0)) return w;  // past the contact's end
    a[k] = {0.0, h * in_frame(segment, s) / (2.0 * cap_ratio_ * delta)};
  }
  // the sixth-order Magnus exponent (Blanes, Casas & Ros, BIT 40, 2000)
  const Su11 alpha_1 = a[1], alpha_2 = std::sqrt(15.0) / 3.0 * (a[2] - a[0]);
  const Su11 alpha_3 = 10.0 / 3.0 * (a[2] - 2.0 * a[1] + a[0]);
  const Su11 c_1 = bracket(alpha_1, alpha_2);
  const Su11 c_2 = -1.0 / 60.0 * bracket(alpha_1, 2.0 * alpha_3 + c_1);
  const Su11 omega = alpha_1 + 1.0 / 12.0 * alpha_3 +
                     1.0 / 240.0 * bracket(-20.0 * alpha_1 - alpha_3 + c_1, alpha_2 + c_2);
  // omega^2 = mu^2 I, mu^2 = |b|^2 - r^2 real: exp(omega) = cosh(mu) I + sinh(mu) / mu omega (cos
  // and sin of |mu| where mu^2 < 0), taken up to a common factor (w = u / v): C = 1, S =
  // tanh(mu) / mu where mu > 1
  const double mu_squared = std::norm(omega.b) - omega.r * omega.r;
  const double mu = std::sqrt(std::abs(mu_squared));
  double C = 1.0, S = 1.0;
  if (mu_squared > 1.0) {
    S = std::tanh(mu) / mu;
  } else if (mu_squared > 0.0) {
    C = std::cosh(mu);
    S = std::sinh(mu) / mu;
  } else if (mu_squared < 0.0) {
    C = std::cos(mu);
    S = std::sin(mu) / mu;
  }
  const std::complex<double> i_r(0.0, omega.r);
  const std::complex<double> u = C * w + S * (i_r * w + omega.b);
  const std::complex<double> v = C + S * (std::conj(omega.b) * w - i_r);
  const std::complex<double> next = u * std::conj(v);  // u / v up to |v|^2
  return next / std::sqrt(std::norm(next));
}

std::complex<double> SpatialPlay::direction_at(const SpatialSegment& segment, double s) const {
  const DirectionNode* first = nodes_.data() + segment.first_node;
  const DirectionNode* below =
      std::upper_bound(first, first + segment.nodes, s,
                       [](double at, const DirectionNode& node) { return at < node.at; });
  const DirectionNode& node = below == first ? *first : below[-1];
  return turned(segment, node.w, node.at, s);
}

Eigen::Vector3d SpatialPlay::stretch_at(const SpatialSegment& segment, double s) const {
  const Eigen::Vector3d n = unit_normal(s);
  switch (segment.regime) {
    case Regime::open:
      return Eigen::Vector3d::Zero();
    case Regime::stick:
      return on_plane(
          segment.start + value(slip_integral_, s) - value(slip_integral_, segment.from), n);
    case Regime::slip: {
      const std::complex<double> w = direction_at(segment, s);
      const Eigen::Vector3d d =
          on_plane(w.real() * segment.start + w.imag() * segment.across, n).normalized();
      return cap_ratio_ * std::max(overlap_(s), 0.0) * d;
    }
  }
  return Eigen::Vector3d::Zero();
}

void SpatialPlay::add_node(double at, std::complex<double> w) {
  nodes_[node_count_++] = {.at = at, .w = w};
}

std::size_t SpatialPlay::pieces_for(const SpatialSegment& segment) const {
  const double span = until_ - segment.from;
  double turn = 0.0;  // the largest of |s| / r_c at the span's Gauss nodes, times the span
  for (double node : {-1.0, 0.0, 1.0}) {
    const double s = segment.from + span * (0.5 + node * std::sqrt(15.0) / 10.0);
    const double delta = overlap_(s);
    if (!(delta > 0.0)) return kDirectionPieces;
    turn = std::max(turn, std::abs(in_frame(segment, s)) / (cap_ratio_ * delta) * span);
  }
  const double pieces = std::ceil(pieces_per_turn_ * std::pow(turn, 7.0 / 6.0));
  return pieces < double(kDirectionPieces) ? std::max(std::size_t(pieces), std::size_t(1))
                                           : kDirectionPieces;
}

SpatialSegment SpatialPlay::slip_from(double at, const Eigen::Vector3d& toward) {
  const Eigen::Vector3d n = unit_normal(at);
  SpatialSegment segment{.from = at, .regime = Regime::slip};
  segment.start = on_plane(toward, n).normalized();
  segment.across = n.cross(segment.start);
  segment.first_node = node_count_;
  add_node(at, 1.0);
  const std::size_t pieces = pieces_for(segment);
  const double piece = (until_ - at) / double(pieces);
  for (std::size_t k = 0; k < pieces; ++k) {
    const DirectionNode& last = nodes_[node_count_ - 1];
    const double next = k + 1 == pieces ? until_ : at + double(k + 1) * piece;
    add_node(next, turned(segment, last.w, last.at, next));
  }
  segment.nodes = node_count_ - segment.first_node;
  return segment;
}

void SpatialPlay::start(const Eigen::Vector3d& stretch) {
  const double overlap = overlap_(0.0);
  if (!(overlap > 0.0)) {
    segments_[0] = {.regime = Regime::open};
    return;
  }
  const double cap = cap_ratio_ * overlap;
  const Eigen::Vector3d xi = on_plane(stretch, unit_normal(0.0));
  const double size = xi.norm();
  if (size >= cap * (1.0 - kOnTheCap) && size > 0.0 &&
      xi.dot(value(slip_, 0.0)) / size > cap_ratio_ * overlap_rate_(0.0)) {
    segments_[0] = slip_from(0.0, xi);
    return;
  }
  segments_[0] = {.regime = Regime::stick,
                  .start = size > cap ? Eigen::Vector3d(cap / size * xi) : xi};
}

double SpatialPlay::watched(const SpatialSegment& segment, double s) const {
  const double delta = overlap_(s);
  switch (segment.regime) {
    case Regime::open:  // until the contact closes
      return -delta;
    case Regime::stick:  // until the stretch reaches the cap, or the contact opens
      return std::min(cap_ratio_ * delta - stretch_at(segment, s).norm(), delta);
    case Regime::slip: {  // until the slip no longer outruns the cap, or the contact opens
      if (!(delta > 0.0)) return delta;
      const double along = std::real(std::conj(direction_at(segment, s)) * in_frame(segment, s));
      return std::min(along - cap_ratio_ * overlap_rate_(s), delta);
    }
  }
  return delta;
}

SpatialSegment SpatialPlay::after(const SpatialSegment& ended, double at) {
  if (ended.regime == Regime::open) {  // born: slipping where the slip outruns the cap
    const Eigen::Vector3d slip = value(slip_, at);
    if (slip.norm() > std::max(cap_ratio_ * overlap_rate_(at), 0.0)) return slip_from(at, slip);
    return {.from = at, .regime = Regime::stick};
  }
  if (!(overlap_(at) > 0.0)) return {.from = at, .regime = Regime::open};
  const Eigen::Vector3d stretch = stretch_at(ended, at);
  if (ended.regime == Regime::slip) return {.from = at, .regime = Regime::stick, .start = stretch};
  return slip_from(at, stretch);
}

}  // namespace mimpact::numerics::mindlin
