"""Nguyen & Brogliato's calibration (2011, section 5.2) as one call: the restitution e and the
impact speed V of Melo's chain (an 8 mm striker, 16 beads of 26 mm, then a tapered chain)
fitted to the largest force at each contact of the monodisperse part.

The paper gives Melo et al.'s measured forces as a figure only, so the measurements here are
synthetic: the model's own forces at e = 0.965 and V = 0.62 m/s (the paper's values) with 2 %
Gaussian noise. The fit starts from e = 0.9, V = 0.5 m/s and should give the values back within
two standard errors; the figure draws the data against the fitted model.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/calibrate_restitution.py [--out DIR]
"""

import argparse
import pathlib

import numpy as np

import mimpact

SCENE = pathlib.Path(__file__).resolve().parents[1] / "scenes/paper/melo_type2_q1.json"
CONTACTS = list(range(1, 16))  # between the 16 beads of 26 mm (0: the striker's)
TRUE = {"contact.restitution": 0.965, "strikers.0.velocity": 0.62}
BOUNDS = {"contact.restitution": (0.8, 1.0), "strikers.0.velocity": (0.2, 1.5)}


def scene():
    chain = mimpact.read_scene(SCENE)
    chain.pop("record")
    chain["impact"] = {"integrator": "adaptive", "tolerance": 1e-8}
    return chain


def synthetic_measurements(noise=0.02, seed=7):
    """The peak forces (N) at e = 0.965, V = 0.62 m/s, with `noise` relative Gaussian noise."""
    forces = mimpact.run_chain(scene()).max_forces[CONTACTS]
    return forces * (1.0 + noise * np.random.default_rng(seed).standard_normal(forces.size))


def calibrate(measured, noise=0.02, client=None):
    start = scene()
    start["contact"]["restitution"] = 0.9
    start["strikers"][0]["velocity"] = 0.5
    return mimpact.fit(start, BOUNDS, "max_forces", measured, sigma=noise * measured,
                       contacts=CONTACTS, client=client)


def draw(measured, fitted, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(6.4, 4.2))
    axes.errorbar(CONTACTS, measured, yerr=0.02 * measured, fmt="o", color="black",
                  label="measurements (synthetic, 2 % noise)")
    e, v = fitted.values["contact.restitution"], fitted.values["strikers.0.velocity"]
    axes.plot(CONTACTS, fitted.result.max_forces[CONTACTS], "-", color="tab:red",
              label=f"fitted model: e = {e:.4f}, V = {v:.4f} m/s")
    axes.set_xlabel("contact (bead k-1 | bead k)")
    axes.set_ylabel("largest force (N)")
    axes.set_title("Melo's monodisperse chain: e and V from the peak forces")
    axes.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="build/python-examples", help="directory of the PNG")
    arguments = parser.parse_args()
    measured = synthetic_measurements()
    fitted = calibrate(measured)
    for path, true in TRUE.items():
        value, error = fitted.values[path], fitted.standard_errors[path]
        print(f"{path:22s} {value:.5f} +- {error:.5f}  (true {true}, "
              f"{abs(value - true) / error:.2f} standard errors off)")
    print(f"{fitted.runs} runs; chi^2 = {float(fitted.residuals @ fitted.residuals):.2f} for "
          f"{len(CONTACTS) - 2} degrees of freedom")
    out = pathlib.Path(arguments.out)
    out.mkdir(parents=True, exist_ok=True)
    draw(measured, fitted, out / "calibrate_restitution.png")
    print(f"wrote {out / 'calibrate_restitution.png'}")


if __name__ == "__main__":
    main()
