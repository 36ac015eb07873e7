#pragma once

// Discs in the plane, built by hand for the friction tests: solid spheres moving in a plane (x,
// y and an angle each), their contacts' normal and tangent columns of W and their mass matrix.

#include <Eigen/Dense>
#include <vector>

namespace mimpact::testing {

// Discs in the plane (solid spheres moving in a plane: x, y, angle each), contacts between
// pairs with normal n from the first to the second and tangent t = (-n_y, n_x).
struct Discs {
  std::vector<double> mass, radius;
  Eigen::VectorXd position, velocity;  // (x, y, angle) per disc
  struct Pair {
    int first, second;
  };
  std::vector<Pair> pairs;

  int bodies() const { return int(mass.size()); }
  Eigen::Vector2d centre(int i) const { return position.segment<2>(3 * i); }
  Eigen::Vector2d normal(const Pair& p) const {
    return (centre(p.second) - centre(p.first)).normalized();
  }
  // W's normal and tangent columns: u_n = (v_k - v_i) . n, s = (v_k - v_i) . t - w_k r_k -
  // w_i r_i (the contact points' velocities)
  void columns(Eigen::MatrixXd& w_n, Eigen::MatrixXd& w_t) const {
    const int m = int(pairs.size());
    w_n = w_t = Eigen::MatrixXd::Zero(3 * bodies(), m);
    for (int j = 0; j < m; ++j) {
      const Pair& p = pairs[std::size_t(j)];
      const Eigen::Vector2d n = normal(p), t(-n.y(), n.x());
      w_n.block<2, 1>(3 * p.second, j) = n;
      w_n.block<2, 1>(3 * p.first, j) = -n;
      w_t.block<2, 1>(3 * p.second, j) = t;
      w_t.block<2, 1>(3 * p.first, j) = -t;
      w_t(3 * p.second + 2, j) = -radius[std::size_t(p.second)];
      w_t(3 * p.first + 2, j) = -radius[std::size_t(p.first)];
    }
  }
  Eigen::VectorXd inverse_mass() const {
    Eigen::VectorXd inverse(3 * bodies());
    for (int i = 0; i < bodies(); ++i) {
      const double m = mass[std::size_t(i)], r = radius[std::size_t(i)];
      inverse.segment<3>(3 * i) << 1.0 / m, 1.0 / m, 1.0 / (0.4 * m * r * r);
    }
    return inverse;
  }
};

// the discs' kinetic energy at velocities v (J)
inline double energy_of(const Discs& d, const Eigen::VectorXd& v) {
  return 0.5 * v.dot(d.inverse_mass().cwiseInverse().cwiseProduct(v));
}

}  // namespace mimpact::testing
