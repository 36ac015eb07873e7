"""The last ball's velocity of Nakagawa's tapered chain (19 steel balls, each 1 - q times the
previous one's radius, struck by a 5 mm ball at 1 m/s) over the taper q and the restitution e,
drawn as a heat map: a sweep of 8 x 6 runs of the adaptive LZB integrator on the local cores,
or on a Dask cluster with --scheduler ADDRESS.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/taper_sweep.py [--out DIR]
"""

import argparse
import pathlib

import numpy as np

import mimpact

SCENE = pathlib.Path(__file__).resolve().parents[1] / "scenes/paper/nakagawa_e0955.json"
TAPERS = np.linspace(0.0, 0.14, 8)
RESTITUTIONS = np.linspace(0.9, 1.0, 6)


def last_ball_velocities(client=None):
    """The last ball's post-impact velocity (m/s), tapers x restitutions."""
    scene = mimpact.read_scene(SCENE)
    scene["impact"] = {"integrator": "adaptive", "tolerance": 1e-8}
    grid = {"chain.segments.0.taper": TAPERS, "contact.restitution": RESTITUTIONS}
    results = mimpact.sweep(scene, grid, client=client)
    return np.array([r.post_impact_velocities[-1] for r in results]).reshape(
        len(TAPERS), len(RESTITUTIONS))


def draw(velocities, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(6.4, 4.2))
    image = axes.pcolormesh(RESTITUTIONS, TAPERS, velocities, shading="nearest", cmap="viridis")
    figure.colorbar(image, label="last ball's velocity (m/s)")
    axes.set_xlabel("restitution e")
    axes.set_ylabel("taper q")
    axes.set_title("Nakagawa's tapered chain, striker at 1 m/s")
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="build/python-examples", help="directory of the PNG")
    parser.add_argument("--scheduler", help="a Dask scheduler's address, e.g. tcp://host:8786")
    arguments = parser.parse_args()
    client = None
    if arguments.scheduler:
        from distributed import Client
        client = Client(arguments.scheduler)
    velocities = last_ball_velocities(client)
    out = pathlib.Path(arguments.out)
    out.mkdir(parents=True, exist_ok=True)
    draw(velocities, out / "taper_sweep.png")
    print("last ball's velocity (m/s); rows: taper q, columns: restitution e")
    print("   q \\ e " + " ".join(f"{e:8.3f}" for e in RESTITUTIONS))
    for q, row in zip(TAPERS, velocities):
        print(f"{q:8.3f} " + " ".join(f"{v:8.4f}" for v in row))
    print(f"wrote {out / 'taper_sweep.png'}")


if __name__ == "__main__":
    main()
