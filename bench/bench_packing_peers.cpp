// The work-precision study of packings against a DEM code (issue 24, item 4): the same scenes,
// in one benchmark run, by mimpact's compliant contacts in the moving geometry over their
// tolerance and by LAMMPS (Debian's `lammps`: pair_style granular with a pure Hertz normal
// force of the same K, velocity Verlet; bench/peers/lammps_packing.py) over its time step.
// Each run's error is that of the bodies' velocities at the scene's end time, relative to the
// striker's speed, against mimpact at tolerance 1e-10 (which agrees with LAMMPS's most
// accurate step to its round-off: tests/packings/test_packing_convergence.cpp): the root mean
// square over bodies (counter rms_error) and the worst body (worst_error). mimpact's time is
// its run's (summary.json's wall_time: the neighbour lists and the integration; the scene's
// parsing and the lattice's building are not counted), LAMMPS's its own "Loop time" (its
// start-up, neighbour lists included, is not counted); manual time for both; a
// run under a second is repeated, three in all, and the least time kept (least_time).
// When /usr/bin/lmp is absent the LAMMPS runs are skipped with a message. A scene with friction
// (scenes 5 and 6) gives both codes Mindlin's tangential spring under Coulomb's cap (LAMMPS's
// `tangential mindlin`, kt = 8 G* of the material), its beads spinning; its errors take the
// larger of a bead's velocity's and r times its spin's (docs/friction.md, section 3).
// bench/packing_work_precision.py runs this program and writes docs/performance_packings.md.
//
// Names: BM_PackingMimpact/<scene>/<tolerance> (1e-1, 3e-2, 1e-2, ... 1e-9: two a decade, so
// that an error between two runs is interpolated over a third of a decade of tolerance, as
// LAMMPS's over its steps a factor 2 apart), BM_PackingLammps/<scene>/<h> at step
// kLargestStep / 2^h; scenes are numbered as in kScenes.
#include <benchmark/benchmark.h>

#include <unistd.h>
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "mimpact/packings/packing_run.hpp"

namespace {

using namespace mimpact;

struct Scene {
  const char* name;
  const char* lattice;    // the scene's "lattice"
  const char* target;     // of the striker, which flies along +y (planar) or +z
  double end_time;        // s: just after the front has crossed
  double friction = 0.0;  // mu: with Mindlin's tangential spring (LAMMPS's tangential mindlin)
};

const Scene kScenes[] = {
    {"hexagonal 32 x 32", R"({"type": "hexagonal", "rows": 32, "columns": 32, "radius": 0.005})",
     "[0, 16]", 1e-3},
    {"hexagonal 56 x 56", R"({"type": "hexagonal", "rows": 56, "columns": 56, "radius": 0.005})",
     "[0, 28]", 1.75e-3},
    {"hexagonal 100 x 100",
     R"({"type": "hexagonal", "rows": 100, "columns": 100, "radius": 0.005})", "[0, 50]", 3.1e-3},
    {"fcc 20 x 20 x 20",
     R"({"type": "fcc", "layers": 20, "rows": 20, "columns": 20, "radius": 0.005})", "[0, 10, 10]",
     5e-4},
    // a smaller crystal, for the cost against size in space (issue 24, item c)
    {"fcc 10 x 10 x 10",
     R"({"type": "fcc", "layers": 10, "rows": 10, "columns": 10, "radius": 0.005})", "[0, 5, 5]",
     2.5e-4},
    // friction in the moving geometry (issue 46): the beads spin, their contacts stick and slip
    {"hexagonal 32 x 32, mu 0.3",
     R"({"type": "hexagonal", "rows": 32, "columns": 32, "radius": 0.005})", "[0, 16]", 1e-3, 0.3},
    {"fcc 6 x 6 x 6, mu 0.3",
     R"({"type": "fcc", "layers": 6, "rows": 6, "columns": 6, "radius": 0.005})", "[0, 3, 3]", 3e-4,
     0.3}};
constexpr double kYoung = 203e9, kPoisson = 0.3;  // Pa, steel
constexpr double kLargestStep = 1.6e-6;           // s, LAMMPS's coarsest
constexpr double kReferenceTolerance = 1e-10;

std::string scene_text(const Scene& scene, double tolerance) {
  const bool planar = std::string(scene.lattice).find("hexagonal") != std::string::npos;
  char compliant[160], contact[80] = "";
  std::snprintf(compliant, sizeof compliant,
                R"("method": "compliant", "compliant": {"tolerance": %.17g, "end_time": %.17g})",
                tolerance, scene.end_time);
  if (scene.friction > 0.0)
    std::snprintf(contact, sizeof contact, R"("contact": {"restitution": 1, "friction": %.17g}, )",
                  scene.friction);
  return std::string(R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},)") +
         R"("lattice": )" + scene.lattice + R"(, "strikers": [{"target": )" + scene.target +
         R"(, "radius": 0.005, "velocity": )" + (planar ? "[0, 1]" : "[0, 0, 1]") + "}], " +
         contact + compliant + "}";
}

struct Run {
  packings::PackingModel model;
  Eigen::VectorXd velocity;  // per coordinate, at the end time
  Eigen::VectorXd spin;      // rad/s, with friction: per body about z in the plane, three in space
  double run_time = 0.0;     // s: the run's wall time (lists and integration)
  std::int64_t steps = 0;
  granular::MovingContactsStats work;
};

Run run_mimpact(const Scene& scene, double tolerance) {
  const packings::PackingScene parsed =
      packings::parse_packing_scene(scene_text(scene, tolerance), scene.name);
  Run run{packings::build_packing_model(parsed)};
  const granular::SceneRun outcome = packings::run_packing_scene(parsed, run.model);
  run.velocity = outcome.impact.velocity_after;
  run.spin = outcome.impact.angular_velocity_after;
  run.run_time = outcome.impact.wall_time;
  run.steps = outcome.impact.result.steps;
  run.work = outcome.moving;
  return run;
}

const Run& reference(int scene) {
  static std::map<int, Run> references;
  auto found = references.find(scene);
  if (found == references.end())
    found = references.emplace(scene, run_mimpact(kScenes[scene], kReferenceTolerance)).first;
  return found->second;
}

// RMS and worst of |v - v_ref| / V over the bodies; where they spin, of the larger of that and
// r |w - w_ref| / V
void set_errors(benchmark::State& state, const packings::PackingModel& model, const Run& run,
                const Run& reference) {
  const int d = model.dimension, k = d == 3 ? 3 : 1;  // spin components per body
  const bool spins = run.spin.size() == k * model.body_count();
  double sum = 0.0, worst = 0.0;
  for (Eigen::Index b = 0; b < model.body_count(); ++b) {
    double error = (run.velocity.segment(d * b, d) - reference.velocity.segment(d * b, d)).norm();
    if (spins)
      error = std::max(
          error,
          model.radius(b) * (run.spin.segment(k * b, k) - reference.spin.segment(k * b, k)).norm());
    sum += error * error;
    worst = std::max(worst, error);
  }
  const double speed = 1.0;  // the striker's, m/s
  state.counters["rms_error"] = std::sqrt(sum / double(model.body_count())) / speed;
  state.counters["worst_error"] = worst / speed;
  state.counters["bodies"] = double(model.body_count());
}

// The least time (s) of `run` (which returns its time): a run under a second is repeated,
// three in all. This machine's load slows a short run by up to half again, the two codes alike
// or not (one benchmark run measured FCC 10^3 at tolerance 1e-4 in 0.059 s, five repetitions
// in 0.038 to 0.052 s); the least of three is the time the code needs.
template <class Timed>
double least_time(Timed&& run) {
  double least = run();
  for (int again = 1; again < 3 && least < 1.0; ++again) least = std::min(least, run());
  return least;
}

void BM_PackingMimpact(benchmark::State& state, int scene, double tolerance) {
  const Run& truth = reference(scene);
  Run run;
  for (auto _ : state)
    state.SetIterationTime(least_time([&] {
      run = run_mimpact(kScenes[scene], tolerance);
      return run.run_time;
    }));
  set_errors(state, run.model, run, truth);
  state.counters["steps"] = double(run.steps);
  // what the cost is to follow (issue 24, item c): the contacts that carried force and the run's
  // length, and the steps its bodies took
  state.counters["contacts_loaded"] = double(run.work.contacts_loaded);
  state.counters["body_steps"] = double(run.work.member_steps);
  state.counters["duration"] = kScenes[scene].end_time;
  state.SetLabel(kScenes[scene].name);
}

// LAMMPS on the model's bodies, through bench/peers/lammps_packing.py: its loop time (s), or a
// negative number when it did not run; the final velocities per coordinate, and spins.
double run_lammps(const packings::PackingModel& model, const Scene& scene, double step, Run& out) {
  Eigen::VectorXd& velocity = out.velocity;
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("mimpact_lammps_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const int d = model.dimension;
  {
    std::ofstream bodies(dir / "bodies.csv");
    bodies << "x,y,z,radius,mass,vx,vy,vz\n";
    bodies.precision(17);
    for (Eigen::Index b = 0; b < model.body_count(); ++b) {
      for (int k = 0; k < 3; ++k) bodies << (k < d ? model.position(b, k) : 0.0) << ",";
      bodies << model.radius(b) << "," << model.mass(d * b);
      for (int k = 0; k < 3; ++k) bodies << "," << (k < d ? model.velocity(d * b + k) : 0.0);
      bodies << "\n";
    }
  }
  char friction[256] = "";
  if (scene.friction > 0.0)
    std::snprintf(friction, sizeof friction,
                  " --friction %.17g --young %.17g --poisson %.17g --out-spins %s", scene.friction,
                  kYoung, kPoisson, (dir / "w.csv").c_str());
  char command[1400];
  std::snprintf(command, sizeof command,
                "/usr/bin/python3 %s/bench/peers/lammps_packing.py --bodies %s --dimension %d "
                "--hertz-k %.17g --dt %.17g --end-time %.17g --out %s%s",
                MIMPACT_SOURCE_DIR, (dir / "bodies.csv").c_str(), d, model.laws.front().stiffness,
                step, scene.end_time, (dir / "v.csv").c_str(), friction);
  FILE* pipe = popen(command, "r");
  if (!pipe) return -1.0;
  std::string output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  if (pclose(pipe) != 0) return -1.0;
  const auto at = output.rfind("\"loop_time_s\": ");
  if (at == std::string::npos) return -1.0;
  const double loop_time = std::stod(output.substr(at + 15));
  std::ifstream in(dir / "v.csv");
  std::string line;
  std::getline(in, line);  // vx,vy,vz
  velocity.resize(model.mass.size());
  for (Eigen::Index b = 0; b < model.body_count() && std::getline(in, line); ++b) {
    std::istringstream cells(line);
    std::string cell;
    for (int k = 0; k < 3 && std::getline(cells, cell, ','); ++k)
      if (k < d) velocity(d * b + k) = std::stod(cell);
  }
  if (scene.friction > 0.0) {
    std::ifstream spins(dir / "w.csv");
    std::getline(spins, line);     // wx,wy,wz
    const int k = d == 3 ? 3 : 1;  // in the plane, about z only
    out.spin.resize(k * model.body_count());
    for (Eigen::Index b = 0; b < model.body_count() && std::getline(spins, line); ++b) {
      std::istringstream cells(line);
      std::string cell;
      for (int c = 0; c < 3 && std::getline(cells, cell, ','); ++c)
        if (c >= 3 - k) out.spin(k * b + c - (3 - k)) = std::stod(cell);
    }
  }
  fs::remove_all(dir);
  return loop_time;
}

void BM_PackingLammps(benchmark::State& state, int scene, int halvings) {
  if (!std::filesystem::exists("/usr/bin/lmp")) {
    state.SkipWithError(
        "LAMMPS is not installed (apt-get install --no-install-recommends lammps, or "
        "bench/packing_work_precision.py --install-lammps)");
    return;
  }
  // a whole number of steps to the end time, each no longer than kLargestStep / 2^halvings
  const double steps =
      std::ceil(kScenes[scene].end_time * std::pow(2.0, double(halvings)) / kLargestStep);
  const double step = kScenes[scene].end_time / steps;
  const Run& truth = reference(scene);
  Run run;
  for (auto _ : state) {
    bool failed = false;
    const double loop_time = least_time([&] {
      const double time = run_lammps(truth.model, kScenes[scene], step, run);
      failed = failed || time < 0.0;
      return failed ? 2.0 : time;  // no repetition after a failure
    });
    if (failed) {
      state.SkipWithError(
          "LAMMPS did not finish: bench/peers/lammps_packing.py prints why (its --selftest "
          "checks the installation)");
      return;
    }
    state.SetIterationTime(loop_time);
  }
  set_errors(state, truth.model, run, truth);
  state.counters["dt"] = step;
  state.SetLabel(kScenes[scene].name);
}

}  // namespace

// The two codes' runs alternate, coarse to fine, so that a noisy machine slows both alike:
// mimpact at tolerance 1e-1 (its loosest), 3e-2, ... 1e-9, LAMMPS at kLargestStep / 2^0 ... 2^7.
int main(int argc, char** argv) {
  // names built by appending: GCC 12 warns on "literal" + std::string (-Wrestrict)
  auto name = [](const char* code, int scene, const std::string& knob) {
    std::string text = code;
    text += "/";
    text += std::to_string(scene);
    text += "/";
    text += knob;
    return text;
  };
  for (int scene = 0; scene < int(std::size(kScenes)); ++scene)
    for (int level = 0; level <= 16; ++level) {  // tolerance 1e-1 ... 1e-9, two a decade
      const int exponent = 1 + (level + 1) / 2;
      const std::string tolerance = (level % 2 ? "3e-" : "1e-") + std::to_string(exponent);
      benchmark::RegisterBenchmark(name("BM_PackingMimpact", scene, tolerance).c_str(),
                                   BM_PackingMimpact, scene, std::stod(tolerance))
          ->Iterations(1)
          ->UseManualTime()
          ->Unit(benchmark::kSecond);
      if (level % 2 || level / 2 > 7) continue;  // LAMMPS's finest step is 2^7 below its largest
      benchmark::RegisterBenchmark(
          name("BM_PackingLammps", scene, std::to_string(level / 2)).c_str(), BM_PackingLammps,
          scene, level / 2)
          ->Iterations(1)
          ->UseManualTime()
          ->Unit(benchmark::kSecond);
    }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
