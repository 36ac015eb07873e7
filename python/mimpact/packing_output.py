"""What `mimpact packing --out DIR` writes, read back and turned into pictures.

- `load(directory)`: the summary, the bodies and contacts, and the frames, as NumPy arrays.
- `write_paraview(directory)`: two time series of VTK files for ParaView, written with meshio:
  `beads.pvd` (points with radius, velocity, speed and, when they turn, angular_velocity;
  ParaView draws them as spheres with its Glyph filter, scaled by radius) and `contacts.pvd` (segments between the centres, or from a
  centre to the wall, carrying the force as cell and point data; Tube scales by it). In two or
  three dimensions; in the moving geometry the beads are where each frame has them
  (frame_positions.csv), else at the configuration of the impact.
- `render(directory, png)`: one frame drawn with VTK as the ParaView recipe of
  docs/packings.md shows it (python3-vtk9; under xvfb-run without a display).
- `draw_force_chains(directory, png)`: the contact forces as segments of width proportional to
  force at a few instants, the picture granular physicists call force chains.

Run `/usr/bin/python3 -m mimpact.packing_output DIR` to write DIR/paraview/ and DIR/force_chains.png.
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
    m/s), when the bodies turn angular_velocity (frames x bodies x 3, rad/s: about z alone in
    the plane) and, in the moving geometry, position (frames x bodies x dimension, m).
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
        turning = os.path.join(directory, "frame_angular_velocities.csv")
        if os.path.exists(turning):
            _, omega = _table(turning)
            omega = omega[:, 1:].reshape(len(omega), len(data["radius"]), -1)
            if omega.shape[2] == 1:  # about z, in the plane
                omega = np.concatenate([np.zeros(omega.shape[:2] + (2,)), omega], axis=2)
            data["angular_velocity"] = omega
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
    """Writes two time series for ParaView into out (directory/paraview by default): per frame
    out/beads_NNNN.vtu and out/contacts_NNNN.vtu, collected by out/beads.pvd and
    out/contacts.pvd; returns {"beads": path, "contacts": path} of the two collections.

    The beads are vertices carrying `radius`, `velocity` and `speed` (and `angular_velocity`,
    rad/s, when they turn); the contacts are segments
    (each with its own two points) carrying `force` as cell data and as point data, which
    ParaView's Tube filter scales by. Positions are each frame's in the moving geometry, else
    the configuration of the impact, which the LZB model keeps. Two series, not one multiblock:
    a filter applied to beads and contacts at once (Glyph scaled by radius, Tube) breaks on the
    part without its array (docs/packings.md gives the filters)."""
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
    collections = {name: ElementTree.Element("VTKFile", type="Collection", version="0.1")
                   for name in ("beads", "contacts")}
    datasets = {name: ElementTree.SubElement(root, "Collection")
                for name, root in collections.items()}
    for frame, time in enumerate(data["time"]):
        centre = data["position"][frame] if "position" in data else data["centre"]
        velocity = _space(data["velocity"][frame])
        force = data["force"][frame]
        beads = {"radius": data["radius"], "velocity": velocity,
                 "speed": np.linalg.norm(velocity, axis=1)}
        if "angular_velocity" in data:
            beads["angular_velocity"] = data["angular_velocity"][frame]
        meshes = {
            "beads": meshio.Mesh(
                _space(centre), [("vertex", np.arange(bodies).reshape(-1, 1))],
                point_data=beads),
            "contacts": meshio.Mesh(
                _space(contact_segments(data, centre).reshape(-1, data["dimension"])),
                [("line", lines)], point_data={"force": np.repeat(force, 2)},
                cell_data={"force": [force]}),
        }
        for name, mesh in meshes.items():
            file = f"{name}_{frame:04d}.vtu"
            meshio.write(os.path.join(out, file), mesh)
            ElementTree.SubElement(datasets[name], "DataSet", timestep=repr(float(time)),
                                   part="0", file=file)
    paths = {}
    for name, root in collections.items():
        paths[name] = os.path.join(out, f"{name}.pvd")
        ElementTree.ElementTree(root).write(paths[name], xml_declaration=True)
    return paths


def render(directory, png, frame=None, size=(1200, 900), spins=False):
    """Draws one frame as docs/packings.md's ParaView recipe shows it, with VTK (Debian's
    python3-vtk9; under xvfb-run where there is no display): the beads as spheres of their
    radius (Glyph, scaled by radius, factor 2), the contacts as tubes whose radius grows with
    their force (Extract Surface, then Tube varying its radius by the scalar force from 0.1 mm
    to 2.5 mm). `frame`: its index, by default the frame whose contacts carry the most force.
    `spins`: the beads coloured by their angular velocity about z (blue clockwise, red
    counter-clockwise, white at rest, full colour from the 90th percentile of |omega| on; the
    recipe's "Coloring: angular_velocity, Z"), for a run whose beads turn. Writes png and returns its path; write_paraview(directory) first."""
    import vtk

    out = os.path.join(directory, "paraview")
    force = load(directory)["force"]
    index = int(np.argmax(force.sum(axis=1))) if frame is None else frame % len(force)

    def read(name):
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(out, f"{name}_{index:04d}.vtu"))
        reader.Update()
        return reader

    beads = read("beads")
    beads.GetOutput().GetPointData().SetActiveScalars("radius")
    sphere = vtk.vtkSphereSource()
    sphere.SetThetaResolution(24)
    sphere.SetPhiResolution(16)
    glyph = vtk.vtkGlyph3D()
    glyph.SetInputConnection(beads.GetOutputPort())
    glyph.SetSourceConnection(sphere.GetOutputPort())
    glyph.SetScaleModeToScaleByScalar()
    glyph.SetScaleFactor(2.0)  # the sphere source's radius is 0.5
    glyph.SetColorModeToColorByScale()
    contacts = read("contacts")
    surface = vtk.vtkDataSetSurfaceFilter()  # ParaView's Extract Surface
    surface.SetInputConnection(contacts.GetOutputPort())
    surface.Update()
    surface.GetOutput().GetPointData().SetActiveScalars("force")
    tube = vtk.vtkTubeFilter()
    tube.SetInputData(surface.GetOutput())
    tube.SetRadius(1e-4)
    tube.SetVaryRadiusToVaryRadiusByScalar()
    tube.SetRadiusFactor(25.0)
    tube.SetNumberOfSides(12)
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    if spins:
        glyph.SetColorModeToColorByScalar()
        glyph.SetInputArrayToProcess(3, 0, 0, 0, "angular_velocity")  # the colouring array
        glyph.Update()
        from vtk.util.numpy_support import vtk_to_numpy
        omega = vtk_to_numpy(beads.GetOutput().GetPointData().GetArray("angular_velocity"))[:, 2]
        # the range of most beads, so that a striker spinning fast does not wash them out
        largest = max(float(np.percentile(np.abs(omega), 90)), 1e-300)
    for source, colour, opacity in ((glyph, (0.75, 0.75, 0.78), 0.35 if not spins else 1.0),
                                    (tube, (0.8, 0.1, 0.1), 1.0)):
        mapper = vtk.vtkPolyDataMapper()
        mapper.SetInputConnection(source.GetOutputPort())
        mapper.ScalarVisibilityOff()
        if spins and source is glyph:
            diverging = vtk.vtkColorTransferFunction()
            diverging.AddRGBPoint(-largest, 0.23, 0.30, 0.75)
            diverging.AddRGBPoint(0.0, 0.95, 0.95, 0.95)
            diverging.AddRGBPoint(largest, 0.71, 0.02, 0.15)
            mapper.SetLookupTable(diverging)
            mapper.ScalarVisibilityOn()
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SelectColorArray("angular_velocity")
            mapper.SetArrayComponent(2)
            mapper.SetColorModeToMapScalars()
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().SetColor(*colour)
        actor.GetProperty().SetOpacity(opacity)
        renderer.AddActor(actor)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(*size)
    renderer.ResetCamera()
    window.Render()
    image = vtk.vtkWindowToImageFilter()
    image.SetInput(window)
    image.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(str(png))
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()
    return png


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
    for path in write_paraview(sys.argv[1]).values():
        print(path)
    print(draw_force_chains(sys.argv[1], os.path.join(sys.argv[1], "force_chains.png")))
