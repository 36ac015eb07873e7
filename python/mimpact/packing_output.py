"""What `mimpact packing --out DIR` writes, read back and turned into pictures.

- `load(directory)`: the summary, the bodies and contacts, and the frames, as NumPy arrays.
- `write_paraview(directory)`: a time series of VTK files for ParaView, written with meshio:
  per frame the beads (points with radius, velocity and speed; ParaView draws them as spheres
  with its Glyph filter, scaled by radius) and the contacts (segments between the centres, or
  from a centre to the wall, carrying the force), and `packing.pvd`, the collection ParaView
  opens as one time series. In two or three dimensions; in the moving geometry the beads are
  where each frame has them (frame_positions.csv), else at the configuration of the impact.
- `draw_force_chains(directory, png)`: the contact forces as segments of width proportional to
  force at a few instants, the picture granular physicists call force chains.

Run `python3 -m mimpact.packing_output DIR` to write DIR/paraview/ and DIR/force_chains.png.
"""

import json
import os
import sys
import xml.etree.ElementTree as ElementTree

import numpy as np


def _table(path):
    """A CSV file with a header row: the header's names and the rows as a 2-D array."""
    with open(path) as stream:
        names = stream.readline().strip().split(",")
    values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return names, values


def load(directory):
    """The output of `mimpact packing --out directory` as a dict of NumPy arrays.

    Keys: summary (the parsed summary.json), dimension (2 or 3), centre (bodies x dimension,
    m), radius (m), mass (kg), first, second (per contact; second is -1 for a wall), normal
    (contacts x dimension), point (where each contact touches, m), and when the run kept
    frames, time (s), force (frames x contacts, N), velocity (frames x bodies x dimension,
    m/s) and, in the moving geometry, position (frames x bodies x dimension, m).
    """
    with open(os.path.join(directory, "summary.json")) as stream:
        summary = json.load(stream)
    names, bodies = _table(os.path.join(directory, "bodies.csv"))
    _, contacts = _table(os.path.join(directory, "contacts.csv"))
    d = 3 if "z" in names else 2
    data = {
        "summary": summary,
        "dimension": d,
        "centre": bodies[:, 1:1 + d],
        "radius": bodies[:, 1 + d],
        "mass": bodies[:, 2 + d],
        "first": contacts[:, 1].astype(int),
        "second": contacts[:, 2].astype(int),
        "normal": contacts[:, 4:4 + d],
        "point": contacts[:, 4 + d:4 + 2 * d],
    }
    forces = os.path.join(directory, "frame_forces.csv")
    if os.path.exists(forces):
        _, force = _table(forces)
        _, velocity = _table(os.path.join(directory, "frame_velocities.csv"))
        data["time"] = force[:, 0]
        data["force"] = force[:, 1:]
        data["velocity"] = velocity[:, 1:].reshape(len(velocity), -1, d)
        positions = os.path.join(directory, "frame_positions.csv")
        if os.path.exists(positions):
            _, position = _table(positions)
            data["position"] = position[:, 1:].reshape(len(position), -1, d)
    return data


def contact_segments(data, centre=None):
    """Per contact, its two ends (contacts x 2 x dimension, m): the centres of its bodies
    (`centre`, bodies x dimension, the configuration of the impact by default), or a centre
    and the point where the bead touches its wall."""
    centre = data["centre"] if centre is None else centre
    start = centre[data["first"]]
    wall = data["second"] < 0
    # a wall's normal points to the beads: the bead touches it a radius behind its centre
    touch = start - data["radius"][data["first"]][:, None] * data["normal"]
    end = np.where(wall[:, None], touch, centre[np.maximum(data["second"], 0)])
    return np.stack([start, end], axis=1)


def _space(points):
    """Points of two or three components as three (ParaView's)."""
    return np.column_stack([points, np.zeros((len(points), 3 - points.shape[1]))])


def write_paraview(directory, out=None):
    """Writes out/beads_NNNN.vtu, out/contacts_NNNN.vtu per frame and out/packing.pvd
    (out defaults to directory/paraview); returns the path of packing.pvd. Positions are each
    frame's in the moving geometry, else the configuration of the impact, which the LZB model
    keeps."""
    import meshio

    data = load(directory)
    if "time" not in data:
        raise ValueError(
            f"{directory} holds no frames; run the scene with \"record\": {{\"frames\": k}} "
            "and --out")
    out = out or os.path.join(directory, "paraview")
    os.makedirs(out, exist_ok=True)
    bodies = len(data["radius"])
    lines = np.arange(2 * len(data["first"])).reshape(-1, 2)
    collection = ElementTree.Element("VTKFile", type="Collection", version="0.1")
    datasets = ElementTree.SubElement(collection, "Collection")
    for frame, time in enumerate(data["time"]):
        centre = data["position"][frame] if "position" in data else data["centre"]
        points = _space(centre)
        contact_points = _space(contact_segments(data, centre).reshape(-1, data["dimension"]))
        velocity = _space(data["velocity"][frame])
        beads = meshio.Mesh(
            points, [("vertex", np.arange(bodies).reshape(-1, 1))],
            point_data={"radius": data["radius"], "velocity": velocity,
                        "speed": np.linalg.norm(velocity, axis=1)})
        contacts = meshio.Mesh(contact_points, [("line", lines)],
                               cell_data={"force": [data["force"][frame]]})
        for name, mesh in (("beads", beads), ("contacts", contacts)):
            file = f"{name}_{frame:04d}.vtu"
            meshio.write(os.path.join(out, file), mesh)
            ElementTree.SubElement(datasets, "DataSet", timestep=repr(float(time)),
                                   part="0" if name == "beads" else "1", file=file)
    path = os.path.join(out, "packing.pvd")
    ElementTree.ElementTree(collection).write(path, xml_declaration=True)
    return path


def draw_force_chains(directory, png, instants=4, axes=None):
    """Draws the contact forces at `instants` frames spread over the impact, each segment's
    width proportional to its force, and saves the figure as `png`. A three-dimensional
    packing is seen along z (its x-y projection)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    data = load(directory)
    if "time" not in data:
        raise ValueError(f"{directory} holds no frames; record frames with --out")
    frames = np.unique(np.linspace(0, len(data["time"]) - 1, instants).astype(int))
    figure, panels = plt.subplots(1, len(frames), figsize=(3.2 * len(frames), 3.4),
                                  squeeze=False)
    widest = data["force"].max()
    for panel, frame in zip(panels[0], frames):
        centres = data["position"][frame] if "position" in data else data["centre"]
        for centre, radius in zip(centres, data["radius"]):
            panel.add_patch(plt.Circle(centre[:2], radius, fill=False, lw=0.3, color="0.6"))
        force = data["force"][frame]
        segments = contact_segments(data, centres)[:, :, :2]
        panel.add_collection(LineCollection(segments, linewidths=6.0 * force / widest,
                                            colors="firebrick"))
        panel.set_aspect("equal")
        panel.autoscale_view()
        panel.set_axis_off()
        panel.set_title(f"t = {1e6 * data['time'][frame]:.0f} µs", fontsize=9)
    figure.suptitle("contact forces (width ∝ force)", fontsize=10)
    figure.tight_layout()
    figure.savefig(png, dpi=150)
    plt.close(figure)
    return png


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python3 -m mimpact.packing_output DIR  (the --out DIR of mimpact packing)")
    print(write_paraview(sys.argv[1]))
    print(draw_force_chains(sys.argv[1], os.path.join(sys.argv[1], "force_chains.png")))
