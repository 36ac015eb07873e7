#pragma once

#include <string>
#include <vector>

namespace mimpact::granular {

// Time series of a scene's impacts, against the time since the first impact (s): the force of
// the recorded contacts (N) and the velocity of the recorded bodies (m/s, `dimension`
// components each, one after the other).
struct TimeSeries {
  std::vector<int> contacts, bodies;
  int dimension = 1;  // velocity components per body
  std::vector<double> time;
  std::vector<std::vector<double>> force;     // [sample][recorded contact]
  std::vector<std::vector<double>> velocity;  // [sample][dimension * recorded body + component]

  // "time,F_3,F_9" then one row per sample; "time,v_0,v_20" likewise, or "time,vx_0,vy_0,..."
  // in the plane (17 significant digits)
  std::string forces_csv() const;
  std::string velocities_csv() const;
};

// Every contact's force and every coordinate's velocity at a few instants of the impact, for
// pictures of the whole scene (ParaView's time series, force chains).
struct Frames {
  std::vector<double> time;                   // s since the first impact
  std::vector<std::vector<double>> force;     // [frame][contact] (N)
  std::vector<std::vector<double>> velocity;  // [frame][coordinate] (m/s)
  // [frame][body * components + k] (rad/s): when the bodies turn (ContactModel::rotation)
  std::vector<std::vector<double>> angular_velocity;
  // [frame][coordinate] (m): where the bodies are, in the moving geometry; empty in the frozen
  // one, whose configuration is the impact's
  std::vector<std::vector<double>> position;

  bool empty() const { return time.empty(); }
};

// "time,<symbol>x_0,<symbol>y_0,..." (one column per component of each listed body; in one
// dimension "<symbol>_0", or "x_0" without a symbol) then one row per sample of `rows`
// ([sample][dimension * body + component]), 17 significant digits.
std::string vector_csv(const std::vector<double>& time,
                       const std::vector<std::vector<double>>& rows, const std::vector<int>& bodies,
                       int dimension, const std::string& symbol);

}  // namespace mimpact::granular
