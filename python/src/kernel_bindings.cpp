#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "json_conversion.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_ds.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/kernel/registry.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/lzb_law.hpp"
#include "mimpact/plugins/register_plugins.hpp"

namespace py = pybind11;

namespace mimpact::python {

namespace {

using kernel::Index;
using kernel::MatrixXd;
using kernel::VectorXd;

// A dict of options (None for none) as the registries' parameters.
kernel::Parameters parameters(const py::object& options, const std::string& where) {
  if (options.is_none()) return kernel::Parameters::object();
  nlohmann::ordered_json json = to_json(options, where);
  if (!json.is_object())
    throw InvalidInput(where + " = " + json.dump() + " is not allowed; allowed: a dict of options");
  return kernel::Parameters(json);
}

// The result of a Python callable as a float64 array of at least `dimensions` dimensions, or
// InvalidInput naming the callable and what it returned.
template <class Matrix>
Matrix numbers_of(const py::object& value, int dimensions, const std::string& what,
                  const std::string& allowed) {
  const py::module_ numpy = py::module_::import("numpy");
  Matrix result;
  try {
    result = py::cast<Matrix>(numpy.attr(dimensions == 1 ? "atleast_1d" : "atleast_2d")(
        numpy.attr("asarray")(value, "float64")));
  } catch (const py::error_already_set&) {
    throw InvalidInput(what + " returned " + short_repr(value) + "; allowed: " + allowed);
  } catch (const py::cast_error&) {
    throw InvalidInput(what + " returned " + short_repr(value) + "; allowed: " + allowed);
  }
  // None reads as NaN: the run stops here rather than carry it
  if (!result.allFinite())
    throw InvalidInput(what + " returned " + short_repr(value) +
                       ", not finite; allowed: " + allowed);
  return result;
}

// The result of a Python callable as a vector of `size` values, or an error naming the callable.
VectorXd vector_result(const py::object& value, Index size, const std::string& what) {
  const std::string allowed = std::to_string(size) +
                              (size == 1 ? " finite number" : " finite numbers") +
                              " (the system's coordinates)";
  const VectorXd result = numbers_of<VectorXd>(value, 1, what, allowed);
  if (result.size() != size)
    throw InvalidInput(what + " returned " + std::to_string(result.size()) +
                       " values; allowed: " + allowed);
  return result;
}

// LagrangianDS with Python callables: each call takes the GIL, which the run released.
std::shared_ptr<kernel::LagrangianDS> lagrangian_ds(VectorXd q, VectorXd v, py::object mass,
                                                    py::object internal_force,
                                                    py::object external_force, std::string name) {
  const Index n = q.size();
  std::shared_ptr<kernel::LagrangianDS> system;
  if (PyCallable_Check(mass.ptr())) {
    system = std::make_shared<kernel::LagrangianDS>(
        std::move(q), std::move(v),
        [mass, n, name](const VectorXd& position, MatrixXd& out) {
          py::gil_scoped_acquire python;
          const std::string what = "system '" + name + "': mass(q)";
          const MatrixXd matrix = numbers_of<MatrixXd>(
              mass(position), 2, what,
              "a finite " + std::to_string(n) + " x " + std::to_string(n) + " matrix");
          if (matrix.rows() != n || matrix.cols() != n)
            throw InvalidInput(
                "system '" + name + "': mass(q) returned a " + std::to_string(matrix.rows()) +
                " x " + std::to_string(matrix.cols()) + " matrix; allowed: " + std::to_string(n) +
                " x " + std::to_string(n));
          out = matrix;
        },
        name);
  } else {
    const MatrixXd matrix = numbers_of<MatrixXd>(mass, 2, "system '" + name + "': mass",
                                                 "a finite matrix or a callable");
    system = std::make_shared<kernel::LagrangianDS>(std::move(q), std::move(v), matrix, name);
  }
  if (!internal_force.is_none())
    system->set_internal_force([internal_force, n, name](double t, const VectorXd& position,
                                                         const VectorXd& velocity, VectorXd& out) {
      py::gil_scoped_acquire python;
      out = vector_result(internal_force(t, position, velocity), n,
                          "system '" + name + "': internal_force(t, q, v)");
    });
  if (!external_force.is_none())
    system->set_external_force([external_force, n, name](double t, VectorXd& out) {
      py::gil_scoped_acquire python;
      out = vector_result(external_force(t), n, "system '" + name + "': external_force(t)");
    });
  return system;
}

// An observer of Python callables, each optional: on_step returns None to go on, or a string,
// the reason to end the run. Each callable receives the Python Simulation (which a callable may
// keep: it keeps the simulation alive) and a copy of the report.
class PythonObserver : public kernel::SimulationObserver {
 public:
  py::object on_start_, on_step_, on_event_, on_impact_, on_output_, on_end_;
  py::handle owner_;  // the Python Simulation that runs; set by its run()

  void on_start(const kernel::Simulation&) override { call(on_start_); }
  kernel::EventStatus on_step(const kernel::Simulation&, const kernel::StepReport& step) override {
    if (on_step_.is_none()) return kernel::EventStatus::proceed();
    py::gil_scoped_acquire python;
    const py::object answer = on_step_(owner_, py::cast(step, py::return_value_policy::copy));
    if (answer.is_none()) return kernel::EventStatus::proceed();
    if (!py::isinstance<py::str>(answer))
      throw InvalidInput("on_step returned " + short_repr(answer) +
                         "; allowed: None to go on, or a string saying why the run ends");
    return kernel::EventStatus::terminate(answer.cast<std::string>());
  }
  void on_event(const kernel::Simulation&, const kernel::StepReport& step) override {
    call(on_event_, step);
  }
  void on_impact(const kernel::Simulation&, const kernel::ImpactReport& report) override {
    call(on_impact_, report);
  }
  void on_output(const kernel::Simulation&) override { call(on_output_); }
  void on_end(const kernel::Simulation&) override { call(on_end_); }

 private:
  template <class... Reports>
  void call(const py::object& callable, const Reports&... reports) {
    if (callable.is_none()) return;
    py::gil_scoped_acquire python;
    callable(owner_, py::cast(reports, py::return_value_policy::copy)...);
  }
};

// The simulation and the observers it holds by reference.
struct PythonSimulation {
  std::unique_ptr<kernel::Simulation> simulation;
  std::vector<std::unique_ptr<PythonObserver>> observers;
};

// Runs with the GIL released; the observers hand `self` to their callables.
kernel::RunSummary run_simulation(const py::object& self, double start, double end) {
  PythonSimulation& simulation = self.cast<PythonSimulation&>();
  for (const auto& observer : simulation.observers) observer->owner_ = self;
  py::gil_scoped_release computing;
  return simulation.simulation->run(start, end);
}

PythonSimulation make_simulation(std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                 const std::string& integrator, const py::object& impacts,
                                 const py::object& contact_forces,
                                 const py::object& integrator_options,
                                 const py::object& impact_options,
                                 const py::object& contact_force_options,
                                 double penetration_tolerance) {
  plugins::register_plugins();
  auto one_step = kernel::integrators().create(
      integrator, parameters(integrator_options, "integrator_options"));
  const kernel::OneStepIntegrator::Needs needs = one_step->needs();
  // by default the problems the integrator needs; a name given where none is needed is
  // passed on, for the Simulation to refuse by name
  kernel::SimulationProblems problems;
  if (!impacts.is_none() || needs.impacts)
    problems.impacts =
        kernel::impact_problems().create(impacts.is_none() ? "lzb" : impacts.cast<std::string>(),
                                         parameters(impact_options, "impact_options"));
  if (!contact_forces.is_none() || needs.contact_forces)
    problems.contact_forces = kernel::contact_force_problems().create(
        contact_forces.is_none() ? "acceleration-lcp" : contact_forces.cast<std::string>(),
        parameters(contact_force_options, "contact_force_options"));
  PythonSimulation result;
  result.simulation = std::make_unique<kernel::Simulation>(
      std::move(system), std::move(one_step), std::move(problems),
      kernel::SimulationOptions{.penetration_tolerance = penetration_tolerance});
  return result;
}

numerics::ContactLaw contact_law(const py::kwargs& fields) {
  return kernel::options_from<numerics::ContactLaw>(parameters(fields, "LzbLaw"),
                                                    {.name = "LzbLaw"});
}

// The bodies: DynamicalSystem and its Lagrangian kinds.
void bind_bodies(py::module_& module) {
  py::class_<kernel::DynamicalSystem, std::shared_ptr<kernel::DynamicalSystem>>(
      module, "DynamicalSystem", "A body of the system: its coordinates q and velocities v")
      .def_property_readonly("name", &kernel::DynamicalSystem::name)
      .def_property_readonly("dimension", &kernel::DynamicalSystem::dimension)
      // copies: the run changes the state after they are read
      .def_property_readonly(
          "position", [](const kernel::DynamicalSystem& s) { return VectorXd(s.position()); })
      .def_property_readonly(
          "velocity", [](const kernel::DynamicalSystem& s) { return VectorXd(s.velocity()); })
      .def("set_state", &kernel::DynamicalSystem::set_state, py::arg("position"),
           py::arg("velocity"));

  py::class_<kernel::LagrangianLinearTIDS, kernel::DynamicalSystem,
             std::shared_ptr<kernel::LagrangianLinearTIDS>>(
      module, "LagrangianLinearTIDS",
      "M q'' + C q' + K q = F_ext, constant matrices (Siconos's LagrangianLinearTIDS)")
      .def(py::init([](VectorXd q, VectorXd v, MatrixXd mass, std::optional<MatrixXd> stiffness,
                       std::optional<MatrixXd> damping, std::optional<VectorXd> external_force,
                       std::string name) {
             kernel::LagrangianLinearTIDS::Matrices matrices{
                 .mass = std::move(mass),
                 .stiffness = stiffness.value_or(MatrixXd()),
                 .damping = damping.value_or(MatrixXd()),
                 .external_force = external_force.value_or(VectorXd())};
             return std::make_shared<kernel::LagrangianLinearTIDS>(std::move(q), std::move(v),
                                                                   std::move(matrices), name);
           }),
           py::arg("q"), py::arg("v"), py::arg("mass"), py::kw_only(),
           py::arg("stiffness") = py::none(), py::arg("damping") = py::none(),
           py::arg("external_force") = py::none(), py::arg("name") = "");

  py::class_<kernel::LagrangianDS, kernel::DynamicalSystem, std::shared_ptr<kernel::LagrangianDS>>(
      module, "LagrangianDS",
      "M(q) q'' + F_int(t, q, v) = F_ext(t): the mass a matrix or a callable mass(q), the "
      "forces callables returning arrays (Siconos's LagrangianDS and its sign convention)")
      .def(py::init(&lagrangian_ds), py::arg("q"), py::arg("v"), py::arg("mass"), py::kw_only(),
           py::arg("internal_force") = py::none(), py::arg("external_force") = py::none(),
           py::arg("name") = "");
}

// Relations, laws, interactions and the system that holds them.
void bind_interactions(py::module_& module) {
  py::class_<kernel::Relation, std::shared_ptr<kernel::Relation>>(module, "Relation");
  py::class_<kernel::LinearRelation, kernel::Relation, std::shared_ptr<kernel::LinearRelation>>(
      module, "LinearRelation",
      "the gap g = C q + e on the stacked coordinates of the bodies; `tangents`, 1 or 2 rows of "
      "C's size, the contact points' slip s = T v of a contact with friction")
      .def(py::init([](kernel::RowVectorXd C, double e, std::optional<Eigen::MatrixXd> tangents) {
             return std::make_shared<kernel::LinearRelation>(std::move(C), e,
                                                             tangents.value_or(Eigen::MatrixXd()));
           }),
           py::arg("C"), py::arg("e"), py::kw_only(), py::arg("tangents") = py::none());

  py::class_<kernel::NonSmoothLaw, std::shared_ptr<kernel::NonSmoothLaw>>(module, "NonSmoothLaw");
  py::class_<plugins::LzbLaw, kernel::NonSmoothLaw, std::shared_ptr<plugins::LzbLaw>>(
      module, "LzbLaw",
      "the LZB contact law: stiffness K (N/m^eta), exponent eta (1.5), restitution e (1), "
      "model 'bi-stiffness' or 'mono-stiffness', friction mu (0; > 0 on a relation with "
      "tangents)")
      .def(py::init([](const py::kwargs& fields) {
        return std::make_shared<plugins::LzbLaw>(contact_law(fields));
      }));

  py::class_<kernel::Interaction, std::shared_ptr<kernel::Interaction>>(
      module, "Interaction", "a contact: one or two bodies, its relation and its law")
      .def(py::init<std::shared_ptr<kernel::DynamicalSystem>, std::shared_ptr<kernel::Relation>,
                    std::shared_ptr<kernel::NonSmoothLaw>, std::string>(),
           py::arg("first"), py::arg("relation"), py::arg("law"), py::arg("name") = "")
      .def(py::init<std::shared_ptr<kernel::DynamicalSystem>,
                    std::shared_ptr<kernel::DynamicalSystem>, std::shared_ptr<kernel::Relation>,
                    std::shared_ptr<kernel::NonSmoothLaw>, std::string>(),
           py::arg("first"), py::arg("second"), py::arg("relation"), py::arg("law"),
           py::arg("name") = "")
      .def_property_readonly("name", &kernel::Interaction::name)
      .def_property_readonly("gap", &kernel::Interaction::gap, "m, at the bodies' state")
      .def_property_readonly("velocity", &kernel::Interaction::velocity, "m/s, u = dg/dt");

  py::class_<kernel::NonSmoothDynamicalSystem, std::shared_ptr<kernel::NonSmoothDynamicalSystem>>(
      module, "NonSmoothDynamicalSystem", "the bodies and their interactions")
      .def(py::init<>())
      .def("add", py::overload_cast<std::shared_ptr<kernel::DynamicalSystem>>(
                      &kernel::NonSmoothDynamicalSystem::add))
      .def("add", py::overload_cast<std::shared_ptr<kernel::Interaction>>(
                      &kernel::NonSmoothDynamicalSystem::add))
      .def_property_readonly("system_count", &kernel::NonSmoothDynamicalSystem::system_count)
      .def_property_readonly("interaction_count",
                             &kernel::NonSmoothDynamicalSystem::interaction_count)
      .def(
          "system",
          [](kernel::NonSmoothDynamicalSystem& self, Index k) -> kernel::DynamicalSystem& {
            if (k < 0 || k >= self.system_count())
              throw InvalidInput(invalid_value_message(
                  "system index", k, "0 <= k < " + std::to_string(self.system_count())));
            return self.system(k);
          },
          py::return_value_policy::reference_internal);
}

// What a run reports: impacts, contact forces, steps, the summary.
void bind_reports(py::module_& module) {
  // the integration's result (ImpactReport::result) read as the report's own attributes
  auto of_result = [](auto member) {
    return [member](const kernel::ImpactReport& report) { return report.result.*member; };
  };
  using numerics::ImpactResult;
  py::class_<kernel::ImpactReport>(module, "ImpactReport")
      .def_readonly("time", &kernel::ImpactReport::time)
      .def_readonly("interactions", &kernel::ImpactReport::interactions)
      .def_readonly("velocity_before", &kernel::ImpactReport::velocity_before)
      .def_property_readonly("velocity_after", of_result(&ImpactResult::velocity))
      .def_property_readonly("impulse", of_result(&ImpactResult::impulse))
      .def_property_readonly("max_force", of_result(&ImpactResult::max_force))
      .def_property_readonly("time_of_max_force", of_result(&ImpactResult::time_of_max_force))
      .def_property_readonly("work", of_result(&ImpactResult::work))
      .def_property_readonly("stored_energy", of_result(&ImpactResult::stored_energy))
      .def_property_readonly("tangential_impulse", of_result(&ImpactResult::tangential_impulse),
                             "N s per tangent row of the interactions with friction")
      .def_property_readonly("slip_after", of_result(&ImpactResult::slip),
                             "m/s, the contact points' slip per tangent row after the impact")
      .def_property_readonly("slip_work", of_result(&ImpactResult::slip_work),
                             "J per interaction, what slip dissipated")
      .def_property_readonly("steps", of_result(&ImpactResult::steps))
      .def_property_readonly("duration", of_result(&ImpactResult::duration))
      .def_readonly("wall_time", &kernel::ImpactReport::wall_time);
  py::class_<kernel::ContactForces>(module, "ContactForces")
      .def_readonly("time", &kernel::ContactForces::time)
      .def_readonly("interactions", &kernel::ContactForces::interactions)
      .def_readonly("force", &kernel::ContactForces::force)
      .def_readonly("acceleration", &kernel::ContactForces::acceleration);
  using kernel::ContactForceHistory;
  py::class_<ContactForceHistory>(
      module, "ContactForceHistory",
      "the compliant contacts' forces since the run began, per interaction: force now, max_force "
      "and time_of_max_force, impulse (N s), the ledger's work, stored_energy and "
      "stored_energy_at_start (J); with friction, tangential_impulse (N s, two columns per "
      "interaction, its tangent rows) and slip_work (J), empty otherwise")
      .def_readonly("force", &ContactForceHistory::force)
      .def_readonly("max_force", &ContactForceHistory::max_force)
      .def_readonly("time_of_max_force", &ContactForceHistory::time_of_max_force)
      .def_readonly("impulse", &ContactForceHistory::impulse)
      .def_readonly("all_open", &ContactForceHistory::all_open)
      .def_readonly("work", &ContactForceHistory::work)
      .def_readonly("stored_energy", &ContactForceHistory::stored_energy)
      .def_readonly("stored_energy_at_start", &ContactForceHistory::stored_energy_at_start)
      .def_readonly("work_of_forces", &ContactForceHistory::work_of_forces)
      .def_readonly("tangential_impulse", &ContactForceHistory::tangential_impulse)
      .def_readonly("slip_work", &ContactForceHistory::slip_work);
  py::class_<kernel::StepReport>(module, "StepReport")
      .def_readonly("time", &kernel::StepReport::time)
      .def_readonly("event", &kernel::StepReport::event)
      .def_readonly("closing", &kernel::StepReport::closing)
      .def_readonly("detaching", &kernel::StepReport::detaching)
      .def_readonly("impact", &kernel::StepReport::impact)
      .def_readonly("contact_forces", &kernel::StepReport::contact_forces)
      .def_readonly("smooth_steps", &kernel::StepReport::smooth_steps);
  py::class_<kernel::RunSummary>(module, "RunSummary")
      .def_property_readonly(
          "status", [](const kernel::RunSummary& s) { return kernel::to_string(s.status); })
      .def_readonly("reason", &kernel::RunSummary::reason)
      .def_readonly("end_time", &kernel::RunSummary::end_time)
      .def_readonly("smooth_steps", &kernel::RunSummary::smooth_steps)
      .def_readonly("events", &kernel::RunSummary::events)
      .def_readonly("impacts", &kernel::RunSummary::impacts)
      .def_readonly("wall_time", &kernel::RunSummary::wall_time);
}

// The generic simulation loop and its observers.
void bind_simulation(py::module_& module) {
  py::class_<PythonSimulation>(
      module, "Simulation",
      "the generic simulation loop over a system, its integrator and problems chosen by registry "
      "name (with their options as dicts); the problems default to the integrator's needs: "
      "'lzb' impacts and 'acceleration-lcp' contact forces")
      .def(py::init(&make_simulation), py::arg("system"), py::kw_only(),
           py::arg("integrator") = "event-driven", py::arg("impacts") = py::none(),
           py::arg("contact_forces") = py::none(), py::arg("integrator_options") = py::none(),
           py::arg("impact_options") = py::none(), py::arg("contact_force_options") = py::none(),
           py::arg("penetration_tolerance") = 1e-9)
      .def(
          "add_observer",
          [](PythonSimulation& self, py::object on_step, py::object on_impact, py::object on_event,
             py::object on_output, py::object on_start, py::object on_end) {
            auto observer = std::make_unique<PythonObserver>();
            observer->on_step_ = std::move(on_step);
            observer->on_impact_ = std::move(on_impact);
            observer->on_event_ = std::move(on_event);
            observer->on_output_ = std::move(on_output);
            observer->on_start_ = std::move(on_start);
            observer->on_end_ = std::move(on_end);
            self.simulation->add_observer(*observer);
            self.observers.push_back(std::move(observer));
          },
          py::kw_only(), py::arg("on_step") = py::none(), py::arg("on_impact") = py::none(),
          py::arg("on_event") = py::none(), py::arg("on_output") = py::none(),
          py::arg("on_start") = py::none(), py::arg("on_end") = py::none(),
          "callables (simulation, report): on_step(simulation, step) returns None to go on or a "
          "string to end the run; on_impact(simulation, impact); on_event(simulation, step); "
          "on_output(simulation) at scheduled times; on_start, on_end(simulation). They receive "
          "this Simulation and copies of the reports, which they may keep")
      .def(
          "schedule_outputs",
          [](PythonSimulation& self, double start, double interval, double end) {
            self.simulation->schedule_outputs(start, interval, end);
          },
          py::arg("start"), py::arg("interval"), py::arg("end"))
      .def("run", &run_simulation, py::arg("start"), py::arg("end"),
           "runs from start to end (s, finite); a second run while one goes on, from any thread, "
           "raises RuntimeError")
      .def_property_readonly("time",
                             [](const PythonSimulation& self) { return self.simulation->time(); })
      .def_property_readonly(
          "contact_force_history",
          [](const PythonSimulation& self) -> const kernel::ContactForceHistory* {
            return self.simulation->integrator().contact_force_history();
          },
          py::return_value_policy::reference_internal,
          "the integrator's ContactForceHistory (the compliant integrator's), or None")
      .def_property_readonly(
          "system",
          [](const PythonSimulation& self) -> const kernel::NonSmoothDynamicalSystem& {
            return self.simulation->system();
          },
          py::return_value_policy::reference_internal);
}

}  // namespace

void bind_kernel(py::module_& module) {
  bind_bodies(module);
  bind_interactions(module);
  bind_reports(module);
  bind_simulation(module);
}

}  // namespace mimpact::python
