// The generic loop of the kernel with an integrator and problems of the test's own: output
// times, events, impacts, observers, termination, the run summary, the problems handed to the
// integrator, the law check, the registry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/kernel/registry.hpp"
#include "mimpact/kernel/simulation.hpp"

namespace mimpact::kernel {
namespace {

class TestLaw : public NonSmoothLaw {
 public:
  std::string_view kind() const override { return "test"; }
};
class OtherLaw : public NonSmoothLaw {
 public:
  std::string_view kind() const override { return "other"; }
};

// Reverses the relative velocity of the closed contacts: u+ = -u-.
class ReversingImpacts : public ImpactProblem {
 public:
  std::string_view name() const override { return "reversing"; }
  void check_law(const NonSmoothLaw& law, const std::string& which) const override {
    if (!dynamic_cast<const TestLaw*>(&law)) throw InvalidInput(which + ": not a test law");
  }
  ImpactReport solve(NonSmoothDynamicalSystem& system, std::span<const Index> closed,
                     double time) override {
    ++calls;
    ImpactReport report;
    report.time = time;
    report.interactions.assign(closed.begin(), closed.end());
    VectorXd v = system.system(0).velocity();
    system.system(0).set_state(system.system(0).position(), -v);
    return report;
  }
  int calls = 0;
};

class NoForces : public ContactForceProblem {
 public:
  std::string_view name() const override { return "none"; }
  void check_law(const NonSmoothLaw&, const std::string&) const override {}
  ContactForces solve(const NonSmoothDynamicalSystem&, std::span<const Index> persistent, double,
                      const VectorXd&, const VectorXd&) override {
    ContactForces forces;
    forces.interactions.assign(persistent.begin(), persistent.end());
    forces.solved = true;
    return forces;
  }
};

// Uniform motion of system 0, with an impact of interaction 0 every `period` seconds.
class PeriodicImpacts : public OneStepIntegrator {
 public:
  // the period (s) of the impacts, the one option of the test integrator
  struct Options {
    double period = 1.0;
    template <class Self, class Visit>
    static void visit_fields(Self& self, Visit&& field) {
      field("period", self.period, positive("s"));
    }
  };
  explicit PeriodicImpacts(double period) : period_(period) {}
  explicit PeriodicImpacts(Options options) : period_(options.period) {}
  std::string_view name() const override { return "periodic"; }
  Needs needs() const override { return {.impacts = true, .contact_forces = true}; }
  void initialize(NonSmoothDynamicalSystem& system, double start,
                  const EventProblems& problems) override {
    system_ = &system;
    impacts_ = problems.impacts;
    time_ = start;
  }
  StepReport advance(double target) override {
    StepReport report;
    const double next_event = (std::floor(time_ / period_ + 1e-9) + 1.0) * period_;
    const double end = std::min(target, next_event);
    DynamicalSystem& body = system_->system(0);
    body.set_state(body.position() + (end - time_) * body.velocity(), body.velocity());
    time_ = end;
    report.time = end;
    report.smooth_steps = 1;
    if (end == next_event) {
      report.event = true;
      report.closing = {0};
      const std::vector<Index> closed{0};
      report.impact = impacts_->solve(*system_, closed, end);
    }
    return report;
  }
  double time() const override { return time_; }

 private:
  double period_;
  NonSmoothDynamicalSystem* system_ = nullptr;
  ImpactProblem* impacts_ = nullptr;
  double time_ = 0.0;
};

// Uniform motion and nothing else: it needs no problem.
class Drift : public OneStepIntegrator {
 public:
  std::string_view name() const override { return "drift"; }
  Needs needs() const override { return {}; }
  void initialize(NonSmoothDynamicalSystem&, double start, const EventProblems&) override {
    time_ = start;
  }
  StepReport advance(double target) override {
    time_ = target;
    return {.time = target};
  }
  double time() const override { return time_; }

 private:
  double time_ = 0.0;
};

std::shared_ptr<NonSmoothDynamicalSystem> one_body(std::shared_ptr<NonSmoothLaw> law) {
  auto system = std::make_shared<NonSmoothDynamicalSystem>();
  LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = MatrixXd::Identity(1, 1);
  auto body = std::make_shared<LagrangianLinearTIDS>(VectorXd::Constant(1, 1.0),
                                                     VectorXd::Constant(1, 2.0), matrices, "body");
  system->add(body);
  system->add(std::make_shared<Interaction>(
      body, std::make_shared<LinearRelation>(RowVectorXd::Ones(1), 0.0), std::move(law), "c"));
  return system;
}

class Recorder : public SimulationObserver {
 public:
  void on_start(const Simulation&) override { ++starts; }
  void on_output(const Simulation& simulation) override {
    outputs.push_back(simulation.time());
    positions.push_back(simulation.system().system(0).position()(0));
  }
  void on_event(const Simulation& simulation, const StepReport&) override {
    events.push_back(simulation.time());
  }
  void on_impact(const Simulation&, const ImpactReport& report) override {
    impacts.push_back(report.time);
  }
  EventStatus on_step(const Simulation&, const StepReport& step) override {
    if (step.impact && stop_after_impacts && int(impacts.size()) + 1 == stop_after_impacts)
      return EventStatus::terminate("enough impacts");
    return EventStatus::proceed();
  }
  void on_end(const Simulation&) override { ++ends; }
  std::vector<double> outputs, positions, events, impacts;
  int starts = 0, ends = 0, stop_after_impacts = 0;
};

TEST(SimulationLoop, OutputsEventsAndImpactsInTimeOrder) {
  auto impacts = std::make_unique<ReversingImpacts>();
  ReversingImpacts& counter = *impacts;
  Simulation simulation(
      one_body(std::make_shared<TestLaw>()), std::make_unique<PeriodicImpacts>(0.3),
      {.impacts = std::move(impacts), .contact_forces = std::make_unique<NoForces>()});
  simulation.schedule_outputs(0.0, 0.25, 1.0);
  Recorder recorder;
  simulation.add_observer(recorder);
  const RunSummary summary = simulation.run(0.0, 1.0);

  EXPECT_EQ(summary.status, RunStatus::reached_end);
  EXPECT_DOUBLE_EQ(summary.end_time, 1.0);
  EXPECT_EQ(summary.events, 3);  // 0.3, 0.6, 0.9
  EXPECT_EQ(summary.impacts, 3);
  EXPECT_EQ(counter.calls, 3);
  EXPECT_EQ(summary.advances, 3 + 4);  // three events, four output times reached
  EXPECT_EQ(recorder.outputs, (std::vector<double>{0.0, 0.25, 0.5, 0.75, 1.0}));
  ASSERT_EQ(recorder.impacts.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(recorder.impacts[k], 0.3 * (k + 1), 1e-15);
  // the velocity 2 m/s reverses at each impact: x(0.75) = 1 + 2*0.3 - 2*0.3 + 2*0.15
  EXPECT_NEAR(recorder.positions[3], 1.3, 1e-12);
  EXPECT_EQ(recorder.starts, 1);
  EXPECT_EQ(recorder.ends, 1);
}

// Issue 47 item 9: the documented maximum of 1e9 outputs is a series held as one entry (it was
// 1e9 doubles, 8 GB, and std::bad_alloc); outputs of two series interleave in time order.
TEST(SimulationLoop, ScheduleOfTheMostOutputsIsBoundedInMemory) {
  Simulation simulation(one_body(std::make_shared<TestLaw>()),
                        std::make_unique<PeriodicImpacts>(0.3),
                        {.impacts = std::make_unique<ReversingImpacts>(),
                         .contact_forces = std::make_unique<NoForces>()});
  simulation.schedule_outputs(0.0, 1e-9, 1.0);  // 1e9 + 1 outputs: allowed
  simulation.schedule_outputs(0.0, 2.5e-7, 1e-6);
  EXPECT_THROW(simulation.schedule_outputs(0.0, 1e-10, 1.0), InvalidInput);  // 1e10
  Recorder recorder;
  simulation.add_observer(recorder);
  simulation.run(0.0, 1.0005e-6);
  ASSERT_EQ(recorder.outputs.size(), 1001u + 5u);  // 0, 1e-9, ... 1e-6, and 0, 2.5e-7, ...
  EXPECT_TRUE(std::is_sorted(recorder.outputs.begin(), recorder.outputs.end()));
  EXPECT_NEAR(recorder.outputs.back(), 1e-6, 1e-21);
}

TEST(SimulationLoop, TerminateEndsTheRunAfterTheCurrentAdvance) {
  Simulation simulation(one_body(std::make_shared<TestLaw>()),
                        std::make_unique<PeriodicImpacts>(0.3),
                        {.impacts = std::make_unique<ReversingImpacts>(),
                         .contact_forces = std::make_unique<NoForces>()});
  Recorder recorder;
  recorder.stop_after_impacts = 2;
  simulation.add_observer(recorder);
  const RunSummary summary = simulation.run(0.0, 10.0);
  EXPECT_EQ(summary.status, RunStatus::terminated);
  EXPECT_EQ(summary.reason, "enough impacts");
  EXPECT_NEAR(summary.end_time, 0.6, 1e-15);
  EXPECT_EQ(summary.impacts, 2);
}

// Advancing to times of the caller's own (Drake's AdvanceTo) is the run with outputs at those
// times: the same states there, the same events, and an observer's termination stops it.
TEST(SimulationLoop, AdvanceToTheOutputTimesIsTheRunWithOutputs) {
  auto make = [] {
    return Simulation(one_body(std::make_shared<TestLaw>()), std::make_unique<PeriodicImpacts>(0.3),
                      {.impacts = std::make_unique<ReversingImpacts>(),
                       .contact_forces = std::make_unique<NoForces>()});
  };
  Simulation with_outputs = make();
  with_outputs.schedule_outputs(0.0, 0.25, 1.0);
  Recorder outputs;
  with_outputs.add_observer(outputs);
  const RunSummary whole = with_outputs.run(0.0, 1.0);

  Simulation stepped = make();
  Recorder events;
  stepped.add_observer(events);
  EXPECT_THROW(stepped.advance_to(0.5), Error);  // before initialize
  stepped.initialize(0.0);
  std::vector<double> times, positions;
  for (double t : {0.25, 0.5, 0.75, 1.0}) {
    EXPECT_TRUE(stepped.advance_to(t));
    times.push_back(stepped.time());
    positions.push_back(stepped.system().system(0).position()(0));
  }
  EXPECT_THROW(stepped.advance_to(0.5), InvalidInput);  // behind time()
  const RunSummary summary = stepped.finish();
  EXPECT_EQ(times, std::vector<double>(outputs.outputs.begin() + 1, outputs.outputs.end()));
  EXPECT_EQ(positions, std::vector<double>(outputs.positions.begin() + 1, outputs.positions.end()));
  EXPECT_EQ(events.impacts, outputs.impacts);
  EXPECT_EQ(summary.advances, whole.advances);
  EXPECT_EQ(summary.end_time, whole.end_time);
  EXPECT_EQ(events.starts, 1);
  EXPECT_EQ(events.ends, 1);
  EXPECT_THROW(stepped.finish(), Error);  // after finish

  Simulation stopped = make();
  Recorder two;
  two.stop_after_impacts = 2;
  stopped.add_observer(two);
  stopped.initialize(0.0);
  EXPECT_TRUE(stopped.advance_to(0.5));
  EXPECT_FALSE(stopped.advance_to(10.0));
  EXPECT_NEAR(stopped.time(), 0.6, 1e-15);
  EXPECT_EQ(stopped.finish().status, RunStatus::terminated);
}

TEST(SimulationLoop, ALawTheImpactProblemCannotHandleIsRefusedBeforeTheRun) {
  Simulation simulation(one_body(std::make_shared<OtherLaw>()),
                        std::make_unique<PeriodicImpacts>(0.3),
                        {.impacts = std::make_unique<ReversingImpacts>(),
                         .contact_forces = std::make_unique<NoForces>()});
  Recorder recorder;
  simulation.add_observer(recorder);
  EXPECT_THROW(simulation.run(0.0, 1.0), InvalidInput);
  EXPECT_EQ(recorder.starts, 0);
}

TEST(SimulationLoop, ANonPositiveMassIsRefusedBeforeTheRun) {
  auto system = std::make_shared<NonSmoothDynamicalSystem>();
  LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = MatrixXd::Constant(1, 1, 0.0);
  system->add(std::make_shared<LagrangianLinearTIDS>(VectorXd::Zero(1), VectorXd::Zero(1), matrices,
                                                     "massless"));
  Simulation simulation(system, std::make_unique<PeriodicImpacts>(0.3),
                        {.impacts = std::make_unique<ReversingImpacts>(),
                         .contact_forces = std::make_unique<NoForces>()});
  try {
    simulation.run(0.0, 1.0);
    FAIL();
  } catch (const InvalidInput& error) {
    EXPECT_NE(std::string(error.what()).find("system 'massless'"), std::string::npos)
        << error.what();
  }
}

// A simulation hands its integrator the problems it needs, and refuses to start without one
// of them or with one it would leave unused.
TEST(SimulationLoop, TheIntegratorGetsTheProblemsItNeedsAndNoOthers) {
  auto message = [](auto make) {
    try {
      make();
    } catch (const InvalidInput& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_EQ(message([] {
              Simulation(one_body(std::make_shared<TestLaw>()),
                         std::make_unique<PeriodicImpacts>(0.3),
                         {.impacts = std::make_unique<ReversingImpacts>()});
            }),
            "Simulation: the one-step integrator \"periodic\" needs a contact force problem; "
            "none was given");
  EXPECT_EQ(message([] {
              Simulation(one_body(std::make_shared<TestLaw>()), std::make_unique<Drift>(),
                         {.impacts = std::make_unique<ReversingImpacts>()});
            }),
            "Simulation: the one-step integrator \"drift\" solves no impact problem; "
            "\"reversing\" was given");
  // with no impact problem, no law is checked: the integrator takes any
  Simulation drift(one_body(std::make_shared<OtherLaw>()), std::make_unique<Drift>());
  EXPECT_EQ(drift.run(0.0, 1.0).status, RunStatus::reached_end);
}

TEST(Registry, CreatesByNameAndNamesWhatIsRegistered) {
  Registry<OneStepIntegrator> registry("one-step integrator");
  registry.add<PeriodicImpacts>("periodic");
  EXPECT_EQ(registry.create("periodic", {{"period", 0.5}})->name(), "periodic");
  try {
    registry.create("event-driven");
    FAIL();
  } catch (const InvalidInput& error) {
    EXPECT_NE(std::string(error.what())
                  .find("no one-step integrator named \"event-driven\"; "
                        "registered: periodic"),
              std::string::npos)
        << error.what();
  }
  try {
    registry.create("periodic", {{"perod", 0.5}});
    FAIL();
  } catch (const InvalidInput& error) {
    // the misspelt key is named, with the field it most likely meant
    EXPECT_NE(std::string(error.what())
                  .find("unknown parameter \"perod\" (did you mean \"period\"?); allowed: period"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace mimpact::kernel
