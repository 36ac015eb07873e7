#include "mimpact/analysis/nesterenko.hpp"

#include <array>
#include <boost/math/tools/toms748_solve.hpp>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <numbers>
#include <string>

#include "mimpact/common/error.hpp"

namespace mimpact::analysis {

namespace {

// The solitary waves exist for 0 < y_inf <= (2/3)^(5/2) (Coste, Falcon & Fauve 1997, after eq. 13).
const double kLargestYInfinity = std::pow(2.0 / 3.0, 2.5);

double factor(ForceSite site) { return site == ForceSite::sensor ? 2.0 : 1.0; }

// The potential of eq. 11, y'' = -W'(y).
double potential(double y, double y_inf) {
  return -0.625 * std::pow(y, 1.6) + 0.5 * y * y +
         1.25 * (std::pow(y_inf, 0.8) - std::pow(y_inf, 1.2)) * std::pow(y, 0.8);
}
double potential_slope(double y, double y_inf) {
  return -std::pow(y, 0.6) + y + (std::pow(y_inf, 0.8) - std::pow(y_inf, 1.2)) * std::pow(y, -0.2);
}

// The turning point y_m > y_inf of the orbit that leaves y_inf: W(y_m) = W(y_inf).
double turning_point(double y_inf) {
  const double level = potential(y_inf, y_inf);
  auto excess = [&](double y) { return potential(y, y_inf) - level; };
  // W dips below its level past y_inf and rises through it at y_m (y_m = (5/4)^(5/2) for
  // y_inf -> 0): scan geometrically from y_inf out to 20 for the rise
  double lower = y_inf, upper = y_inf;
  bool dipped = false;
  const int steps = 8000;
  const double growth = std::log(20.0 / y_inf) / steps;
  for (int k = 1; k <= steps; ++k) {
    upper = y_inf * std::exp(growth * k);
    const double e = excess(upper);
    if (e < 0.0) {
      dipped = true;
      lower = upper;
    } else if (dipped) {
      break;
    }
  }
  std::uintmax_t iterations = 200;
  const auto [a, b] = boost::math::tools::toms748_solve(
      [&](double y) { return -excess(y); }, lower, upper,
      [](double x, double y) { return std::abs(y - x) <= 1e-14 * y; }, iterations);
  return 0.5 * (a + b);
}

void check_positive(const std::string& field, double value, const std::string& unit) {
  if (!(value > 0.0 && std::isfinite(value)))
    throw InvalidInput(invalid_value_message(field, value, "a finite value > 0 (" + unit + ")"));
}

void check_chain(const BeadChain& chain) {
  check_positive("bead chain radius", chain.radius, "m");
  check_positive("bead chain young", chain.young, "Pa");
  check_positive("bead chain density", chain.density, "kg/m^3");
  if (!(chain.poisson > -1.0 && chain.poisson < 0.5))
    throw InvalidInput(invalid_value_message("bead chain poisson", chain.poisson, "-1 < nu < 0.5"));
}

}  // namespace

double BeadChain::theta() const { return 3.0 * (1.0 - poisson * poisson) / (4.0 * young); }
double BeadChain::mass() const {
  return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius * density;
}
double BeadChain::C() const {
  return std::sqrt(2.0 * radius * radius * radius / (mass() * theta()));
}

double solitary_wave_speed(const BeadChain& chain, double peak_force, ForceSite site) {
  check_chain(chain);
  check_positive("peak force", peak_force, "N");
  return chain.C() * std::sqrt(0.8) *
         std::pow(factor(site) * chain.theta() * peak_force / (chain.radius * chain.radius),
                  1.0 / 6.0);
}

double solitary_wave_width(const BeadChain& chain, double speed) {
  return std::sqrt(10.0) * chain.radius / speed;
}

PrecompressedWave precompressed_solitary_wave(const BeadChain& chain, double peak_force,
                                              double static_force, ForceSite site) {
  check_chain(chain);
  check_positive("peak force", peak_force, "N");
  check_positive("static force", static_force, "N; 0 is solitary_wave_speed");
  const double a = chain.radius, theta = chain.theta();
  PrecompressedWave wave;
  const double psi_inf = std::pow(theta * static_force, 2.0 / 3.0) / std::pow(a, 4.0 / 3.0);
  wave.sound_speed = chain.C() * std::sqrt(1.5) * std::pow(psi_inf, 0.25);
  // eq. 21 at the sensor (deflection 2^(-1/3) of the beads'); between beads psi ~ F^(2/3)
  const double s = factor(site);
  wave.strain_ratio = (std::pow(s * (peak_force + static_force), 2.0 / 3.0) -
                       std::pow(s * static_force, 2.0 / 3.0) + std::pow(static_force, 2.0 / 3.0)) /
                      std::pow(static_force, 2.0 / 3.0);
  // the strain ratio of the wave that leaves y_inf (eq. 23's orbit)
  auto strain_ratio_of = [](double y_inf) { return std::pow(turning_point(y_inf) / y_inf, 0.8); };
  auto mismatch = [&](double y_inf) { return strain_ratio_of(y_inf) - wave.strain_ratio; };
  const std::uintmax_t max_iterations = 200;
  std::uintmax_t iterations = max_iterations;
  const double high = kLargestYInfinity * (1.0 - 1e-9);
  const double low = 1e-12;
  // a strain ratio outside the range y_inf in [low, high] reaches has no root to bracket
  const double smallest_ratio = strain_ratio_of(high), largest_ratio = strain_ratio_of(low);
  if (!(wave.strain_ratio > smallest_ratio && wave.strain_ratio < largest_ratio))
    throw InvalidInput(invalid_value_message(
        "peak force / static force", peak_force / static_force,
        "a ratio whose strain ratio (here " + to_text(wave.strain_ratio) + ") lies in (" +
            to_text(smallest_ratio) + ", " + to_text(largest_ratio) + "), what eq. 23 resolves"));
  const auto [lower, upper] = boost::math::tools::toms748_solve(
      mismatch, low, high, [](double x, double y) { return std::abs(y - x) <= 1e-13 * y; },
      iterations);
  if (iterations >= max_iterations)
    throw Error("precompressed solitary wave: y_inf not found in " +
                std::to_string(max_iterations) + " iterations for F_m = " + to_text(peak_force) +
                " N, F_0 = " + to_text(static_force) + " N");
  wave.y_infinity = 0.5 * (lower + upper);
  wave.y_max = turning_point(wave.y_infinity);
  wave.speed = wave.sound_speed * std::sqrt(2.0 / 3.0) * std::pow(wave.y_infinity, -0.2);
  return wave;
}

std::vector<std::pair<double, double>> precompressed_pulse(const BeadChain& chain,
                                                           double peak_force, double static_force,
                                                           ForceSite site, int samples) {
  const PrecompressedWave wave = precompressed_solitary_wave(chain, peak_force, static_force, site);
  const double y_inf = wave.y_infinity;
  // y(eta) from y_m (y' = 0) down towards y_inf; xi = sqrt(2/5) a eta = -V t. The orbit
  // reaches y_inf only asymptotically and is unstable there: the pulse ends where y stops
  // falling.
  using State = std::array<double, 2>;
  auto rhs = [&](const State& x, State& dxdt, double) {
    dxdt[0] = x[1];
    dxdt[1] = -potential_slope(std::max(x[0], y_inf), y_inf);
  };
  const double eta_scale = std::sqrt(0.4) * chain.radius / wave.speed;  // t per unit eta
  const double eta_end = 40.0;
  const double s = factor(site);
  auto force_of = [&](double y) {
    // the force beyond the static one (eq. 23 at the sensor; between beads F ~ psi^(3/2))
    const double scaled = std::pow(y / y_inf, 0.8) - 1.0 + std::pow(s, 2.0 / 3.0);
    return static_force / s * (std::pow(std::max(scaled, 0.0), 1.5) - s);
  };
  namespace odeint = boost::numeric::odeint;
  auto stepper = odeint::make_dense_output(1e-12, 1e-12, odeint::runge_kutta_dopri5<State>());
  stepper.initialize(State{wave.y_max, 0.0}, 0.0, 1e-3);
  std::vector<std::pair<double, double>> pulse{{0.0, force_of(wave.y_max)}};
  for (int k = 1; k < samples; ++k) {
    const double eta = eta_end * double(k) / double(samples - 1);
    while (stepper.current_time() < eta) stepper.do_step(rhs);
    State at;
    stepper.calc_state(eta, at);
    if (at[1] >= 0.0) break;  // past the bottom of the orbit
    pulse.emplace_back(eta * eta_scale, force_of(at[0]));
  }
  return pulse;
}

}  // namespace mimpact::analysis
