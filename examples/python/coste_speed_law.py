"""The solitary wave's speed against its force in Coste, Falcon & Fauve's chain (1997): 51
stainless-steel beads of 8 mm struck by a tungsten-carbide bead. Nesterenko's law says
V = A F^(1/6) between two beads, the constant A set by the beads' elasticity; the measured pairs (F_m, V) of
their figures 13-15 (no static load) are fitted here by the same procedure as the calibration
of Melo's chain: mimpact.fit varies the beads' Young's modulus, each run gives the wave's speed
between beads 26 and 46 and its force there, hence the model's A, and the model's speeds at
the measured forces meet the data in the least-squares sense.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/coste_speed_law.py [--out DIR]
"""

import argparse
import pathlib

import numpy as np

import mimpact

SCENE = pathlib.Path(__file__).resolve().parents[1] / "scenes/paper/coste_chain.json"
# (F_m in N, V in m/s), Coste, Falcon & Fauve (1997), figures 13-15, F_0 = 0
MEASURED = np.array([(36.7, 629), (48.5, 659), (61.4, 685), (86.4, 725), (168.5, 811),
                     (216.2, 845), (269.7, 877), (356.4, 919), (473.1, 963), (594.0, 1000),
                     (646.1, 1014), (704.6, 1029)])
FROM, TO = 26, 46  # the contacts the speed is timed between: 20 beads of 8 mm apart


def scene():
    chain = mimpact.read_scene(SCENE)
    chain.pop("record")
    chain["impact"] = {"integrator": "adaptive", "tolerance": 1e-8}
    return chain


def speed_constant(result):
    """A = V / F^(1/6) of the run's wave (m/s / N^(1/6)), its speed between contacts FROM and
    TO and its force at TO, between two beads."""
    distance = (TO - FROM) * 2 * 0.004
    speed = distance / (result.times_of_max_force[TO] - result.times_of_max_force[FROM])
    return speed / result.max_forces[TO] ** (1 / 6)


def model_speeds(result):
    """The model's wave speeds at the measured forces. Their sensor, a plane-sphere contact
    closing the chain, reads half the force between two beads of the same wave (Coste, Falcon &
    Fauve, eqs. 18-20; docs/nesterenko.md)."""
    return speed_constant(result) * (2 * MEASURED[:, 0]) ** (1 / 6)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="build/python-examples", help="directory of the PNG")
    arguments = parser.parse_args()
    nominal = mimpact.run_chain(scene())
    fitted = mimpact.fit(scene(), {"material.young": (1.5e11, 3.5e11)}, model_speeds,
                         MEASURED[:, 1])
    young, error = fitted.values["material.young"], fitted.standard_errors["material.young"]
    a_nominal, a_fitted = speed_constant(nominal), speed_constant(fitted.result)
    rms = lambda result: np.sqrt(np.mean((model_speeds(result) - MEASURED[:, 1]) ** 2))
    print(f"nominal E = 2.26e11 Pa: A = {a_nominal:.2f} m/s/N^(1/6), rms {rms(nominal):.1f} m/s")
    print(f"fitted  E = {young:.4g} +- {error:.2g} Pa: A = {a_fitted:.2f} m/s/N^(1/6), "
          f"rms {rms(fitted.result):.1f} m/s, {fitted.runs} runs")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    forces = np.linspace(30, 720, 100)
    figure, axes = plt.subplots(figsize=(6.4, 4.2))
    axes.plot(MEASURED[:, 0], MEASURED[:, 1], "o", color="black",
              label="Coste, Falcon & Fauve (1997)")
    axes.plot(forces, a_nominal * (2 * forces) ** (1 / 6), "--", color="gray",
              label=f"model, nominal E: A = {a_nominal:.1f}")
    axes.plot(forces, a_fitted * (2 * forces) ** (1 / 6), "-", color="tab:red",
              label=f"model, fitted E = {young / 1e9:.0f} GPa: A = {a_fitted:.1f}")
    axes.set_xlabel("largest force F_m at the sensor (N)")
    axes.set_ylabel("wave speed V (m/s)")
    axes.set_title("Solitary wave speed, V = A (2 F_m)^(1/6)")
    axes.legend()
    figure.tight_layout()
    out = pathlib.Path(arguments.out)
    out.mkdir(parents=True, exist_ok=True)
    figure.savefig(out / "coste_speed_law.png", dpi=120)
    print(f"wrote {out / 'coste_speed_law.png'}")


if __name__ == "__main__":
    main()
