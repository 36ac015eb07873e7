#include "mimpact/numerics/mindlin_spatial_play.hpp"

#include <algorithm>
#include <cmath>

namespace mimpact::numerics::mindlin {

namespace {

constexpr double kOnTheCap = 1e-9;  // relative: a stretch this near the cap starts on it

Eigen::Vector3d on_plane(const Eigen::Vector3d& v, const Eigen::Vector3d& unit_normal) {
  return v - v.dot(unit_normal) * unit_normal;
}

}  // namespace

SpatialPlay::SpatialPlay(const Curve& slip, const StepPolynomial& overlap, const Curve& normal,
                         double cap_ratio, const Eigen::Vector3d& stretch, double until)
    : slip_(slip),
      normal_(normal),
      overlap_(overlap),
      overlap_rate_(overlap.derivative()),
      cap_ratio_(cap_ratio),
      until_(until) {
  for (std::size_t k = 0; k < 3; ++k) slip_integral_[k] = slip[k].antiderivative();
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
  using Matrix = Eigen::Matrix2cd;
  const double h = to - from, middle = 0.5 * (from + to), offset = h * std::sqrt(15.0) / 10.0;
  // A at the three Gauss-Legendre nodes, times h
  std::array<Matrix, 3> a;
  for (std::size_t k = 0; k < 3; ++k) {
    const double s = middle + (double(k) - 1.0) * offset, delta = overlap_(s);
    if (!(delta > 0.0) || !(h > 0.0)) return w;  // past the contact's end
    const std::complex<double> entry = h * in_frame(segment, s) / (2.0 * cap_ratio_ * delta);
    a[k] << 0.0, entry, std::conj(entry), 0.0;
  }
  auto bracket = [](const Matrix& x, const Matrix& y) -> Matrix { return x * y - y * x; };
  // the sixth-order Magnus exponent (Blanes, Casas & Ros, BIT 40, 2000)
  const Matrix alpha_1 = a[1], alpha_2 = std::sqrt(15.0) / 3.0 * (a[2] - a[0]);
  const Matrix alpha_3 = 10.0 / 3.0 * (a[2] - 2.0 * a[1] + a[0]);
  const Matrix c_1 = bracket(alpha_1, alpha_2);
  const Matrix c_2 = -1.0 / 60.0 * bracket(alpha_1, 2.0 * alpha_3 + c_1);
  const Matrix omega =
      alpha_1 + alpha_3 / 12.0 + bracket(-20.0 * alpha_1 - alpha_3 + c_1, alpha_2 + c_2) / 240.0;
  // omega is traceless: omega^2 = mu^2 I, exp(omega) = cosh(mu) I + sinh(mu) / mu omega, taken
  // up to a common factor (w = u / v): C = cosh(mu), S = sinh(mu) / mu where |Re mu| <= 1, else
  // C = 1, S = tanh(mu) / mu
  const std::complex<double> mu = std::sqrt(omega(0, 0) * omega(0, 0) + omega(0, 1) * omega(1, 0));
  std::complex<double> C = 1.0, S = 1.0;
  if (std::abs(mu.real()) > 1.0) {
    S = std::tanh(mu) / mu;
  } else if (std::abs(mu) > 0.0) {
    C = std::cosh(mu);
    S = std::sinh(mu) / mu;
  }
  const std::complex<double> u = C * w + S * (omega(0, 0) * w + omega(0, 1));
  const std::complex<double> v = C + S * (omega(1, 0) * w + omega(1, 1));
  const std::complex<double> next = u / v;
  return next / std::abs(next);
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

SpatialSegment SpatialPlay::slip_from(double at, const Eigen::Vector3d& toward) {
  const Eigen::Vector3d n = unit_normal(at);
  SpatialSegment segment{.from = at, .regime = Regime::slip};
  segment.start = on_plane(toward, n).normalized();
  segment.across = n.cross(segment.start);
  segment.first_node = node_count_;
  add_node(at, 1.0);
  const double piece = (until_ - at) / double(kDirectionPieces);
  for (std::size_t k = 0; k < kDirectionPieces; ++k) {
    const DirectionNode& last = nodes_[node_count_ - 1];
    const double next = k + 1 == kDirectionPieces ? until_ : at + double(k + 1) * piece;
    add_node(next, turned(segment, last.w, last.at, next));
  }
  segment.nodes = node_count_ - segment.first_node;
  return segment;
}

void SpatialPlay::start(const Eigen::Vector3d& stretch) {
  count_ = 1;
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
