"""`mimpact packing --out` read back, written for ParaView with meshio, and drawn."""

import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

import matplotlib.image
import meshio
import numpy as np
import pytest

from conftest import SOURCE, rough_packing
from mimpact import packing_output


def test_paraview_files_hold_the_frames(cli, tmp_path):
    out = tmp_path / "hexagon"
    subprocess.run([cli, "packing", str(SOURCE / "examples/scenes/packings/hexagonal_10x10.json"),
                    "--out", str(out), "--quiet"], check=True)
    data = packing_output.load(out)
    frames = len(data["time"])
    assert frames > 2 and data["force"].shape == (frames, 262)
    # the momentum of every frame is the striker's: the frames are the impact's own states
    momentum = np.einsum("b,fbk->fk", data["mass"], data["velocity"])
    np.testing.assert_allclose(momentum[:, 1], data["mass"][-1] * 1.0, rtol=1e-12)
    np.testing.assert_allclose(momentum[:, 0], 0.0, atol=1e-15)

    collections = packing_output.write_paraview(out)
    for name in ("beads", "contacts"):  # two series, one file per frame each
        datasets = ElementTree.parse(collections[name]).getroot().find("Collection")
        assert [d.get("file") for d in datasets] == [f"{name}_{k:04d}.vtu" for k in range(frames)]
    last = frames - 1
    beads = meshio.read(out / "paraview" / f"beads_{last:04d}.vtu")
    assert len(beads.points) == 101
    np.testing.assert_array_equal(beads.point_data["radius"], data["radius"])
    np.testing.assert_array_equal(beads.point_data["velocity"][:, :2], data["velocity"][last])
    contacts = meshio.read(out / "paraview" / f"contacts_{last:04d}.vtu")
    assert contacts.cells[0].data.shape == (262, 2)
    np.testing.assert_array_equal(contacts.cell_data["force"][0], data["force"][last])
    # and at both ends of its segment, for ParaView's Tube
    np.testing.assert_array_equal(contacts.point_data["force"].reshape(-1, 2),
                                  np.column_stack([data["force"][last]] * 2))
    # a contact's segment joins the centres of its two bodies
    start, end = packing_output.contact_segments(data)[0]
    np.testing.assert_allclose(np.linalg.norm(end - start), 0.01, rtol=1e-12)

    png = packing_output.draw_force_chains(out, out / "chains.png")
    assert (out / "chains.png").stat().st_size > 10_000 and str(png).endswith("chains.png")


def test_a_run_without_frames_is_named(cli, tmp_path):
    scene = tmp_path / "scene.json"
    scene.write_text(
        '{"material": {"density": 7780, "young": 203e9, "poisson": 0.3},'
        ' "lattice": {"type": "square", "rows": 2, "columns": 2, "radius": 0.005},'
        ' "strikers": [{"target": [0, 0], "radius": 0.005, "velocity": [1, 0]}],'
        ' "impact": {"delta_p": 1e-5}}')
    subprocess.run([cli, "packing", str(scene), "--out", str(tmp_path / "out"), "--quiet"],
                   check=True)
    try:
        packing_output.write_paraview(tmp_path / "out")
    except ValueError as error:
        assert "holds no frames" in str(error)
    else:
        raise AssertionError("no error")


def test_a_three_dimensional_packing_opens_where_its_beads_are(cli, tmp_path):
    # an FCC packing in the moving geometry: the ParaView files hold the beads in space, where
    # each frame has them, and the contacts between them
    scene = tmp_path / "fcc.json"
    scene.write_text(
        '{"material": {"density": 7780, "young": 203e9, "poisson": 0.3},'
        ' "lattice": {"type": "fcc", "layers": 3, "rows": 3, "columns": 3, "radius": 0.005},'
        ' "strikers": [{"target": [0, 1, 1], "radius": 0.005, "velocity": [0, 0.3, 1]}],'
        ' "method": "compliant", "compliant": {"tolerance": 1e-8, "end_time": 1e-4},'
        ' "record": {"interval": 1e-6, "frames": 20}}')
    out = tmp_path / "out"
    subprocess.run([cli, "packing", str(scene), "--out", str(out), "--quiet"], check=True)
    data = packing_output.load(out)
    assert data["dimension"] == 3 and data["position"].shape == (len(data["time"]), 28, 3)
    # the frames' momentum is the striker's, in all three components
    momentum = np.einsum("b,fbk->fk", data["mass"], data["velocity"])
    np.testing.assert_allclose(momentum, np.outer(np.ones(len(momentum)),
                                                  data["mass"][-1] * np.array([0, 0.3, 1])),
                               rtol=1e-12, atol=1e-17)
    # the beads move: the last frame is not the first
    assert np.abs(data["position"][-1] - data["position"][0]).max() > 1e-6
    collections = packing_output.write_paraview(out)
    datasets = ElementTree.parse(collections["contacts"]).getroot().find("Collection")
    last = len(data["time"]) - 1
    assert len(datasets) == last + 1
    beads = meshio.read(out / "paraview" / f"beads_{last:04d}.vtu")
    np.testing.assert_array_equal(beads.points, data["position"][last])
    np.testing.assert_array_equal(beads.point_data["velocity"], data["velocity"][last])
    assert np.ptp(beads.points[:, 2]) > 0.01  # three layers
    contacts = meshio.read(out / "paraview" / f"contacts_{last:04d}.vtu")
    ends = contacts.points[contacts.cells[0].data]
    # a contact joins the centres of its beads as they are at that frame
    np.testing.assert_array_equal(ends[:, 0], data["position"][last][data["first"]])
    packing_output.draw_force_chains(out, out / "chains.png")
    assert (out / "chains.png").stat().st_size > 10_000


def _shows_beads_and_force_chains(png, background):
    """The picture holds the packing's beads (grey) and force chains (red tubes) on its
    background, neither blank nor one sphere filling the screen."""
    image = matplotlib.image.imread(png)[:, :, :3]
    red, green, blue = image[..., 0], image[..., 1], image[..., 2]
    empty = (np.abs(image - np.asarray(background)) < 0.02).all(axis=2)
    chains = red - np.maximum(green, blue) > 0.25   # the tubes
    beads = ~empty & ~chains & (np.abs(red - green) < 0.08) & (np.abs(green - blue) < 0.08)
    # measured with VTK: 73 % background, 22 % beads, 3.7 % force chains
    assert 0.2 < empty.mean() < 0.95
    assert beads.mean() > 0.05 and chains.mean() > 0.01
    # the chains run inside the packing, across much of it
    rows, columns = np.nonzero(beads)
    chain_rows, chain_columns = np.nonzero(chains)
    assert rows.min() <= chain_rows.min() and chain_rows.max() <= rows.max()
    assert np.ptp(chain_columns) > 0.5 * np.ptp(columns)


def test_the_paraview_recipe_shows_beads_and_force_chains(cli, tmp_path):
    # docs/packings.md's filters (Glyph by radius; Extract Surface, Tube by force) applied with
    # VTK to the frame of the largest forces, rendered headless: the picture shows the packing's
    # beads and its force chains, neither blank nor one sphere filling the screen
    if shutil.which("xvfb-run") is None:
        pytest.skip("xvfb-run is not installed (Debian's xvfb): the picture is not rendered")
    try:
        import vtk  # noqa: F401
    except ImportError:
        pytest.skip("VTK's Python is not installed (Debian's python3-vtk9)")
    out = tmp_path / "hexagon"
    subprocess.run([cli, "packing", str(SOURCE / "examples/scenes/packings/hexagonal_10x10.json"),
                    "--out", str(out), "--quiet"], check=True)
    packing_output.write_paraview(out)
    png = tmp_path / "render.png"
    subprocess.run(["xvfb-run", "-a", sys.executable, "-c",
                    f"from mimpact import packing_output; "
                    f"packing_output.render({str(out)!r}, {str(png)!r})"],
                   check=True, env=dict(os.environ))
    _shows_beads_and_force_chains(png, (1.0, 1.0, 1.0))
    # and ParaView itself, where installed, with the docs' properties
    pvbatch = shutil.which("pvbatch3.11") or shutil.which("pvbatch")
    if pvbatch is None or subprocess.run(
            ["xvfb-run", "-a", pvbatch, "-c", "import paraview.simple"],
            capture_output=True).returncode != 0:
        # Debian's python3-paraview and python3-vtk9 exclude each other
        pytest.skip("ParaView's Python is not installed (Debian's paraview and python3-paraview, "
                    "which replaces python3-vtk9): the recipe was rendered by VTK only")
    frame = int(np.argmax(packing_output.load(out)["force"].sum(axis=1)))
    subprocess.run(["xvfb-run", "-a", pvbatch, str(SOURCE / "python/tests/paraview_recipe.py"),
                    str(out), str(frame), str(tmp_path / "paraview.png")], check=True)
    _shows_beads_and_force_chains(tmp_path / "paraview.png", (0.32, 0.34, 0.43))


def test_frames_of_a_rough_packing_carry_the_spins(cli, tmp_path):
    """Issue 46: with friction the frames carry every bead's angular velocity, in
    frame_angular_velocities.csv, load() and the ParaView beads; at every frame the bodies
    keep the angular momentum about the origin summary.json gives (the tangential impulses so
    far are internal), and the last frame is the post-impact state."""
    scene = dict(rough_packing(), record={"interval": 2e-6, "frames": 1})
    path = tmp_path / "rough.json"
    path.write_text(json.dumps(scene))
    out = tmp_path / "rough"
    subprocess.run([cli, "packing", str(path), "--out", str(out), "--quiet"], check=True)
    data = packing_output.load(out)
    frames = len(data["time"])
    omega = data["angular_velocity"]
    assert frames > 5 and omega.shape == (frames, 17, 3)
    np.testing.assert_allclose(omega[-1, :, 2], data["summary"]["post_impact_angular_velocities"],
                               rtol=0, atol=1e-12 * 150)
    # angular momentum about the origin at the impact's configuration: the striker has flown
    # no gap, so the bodies are where bodies.csv has them
    inertia = 0.4 * data["mass"] * data["radius"] ** 2
    centre, velocity = data["centre"], data["velocity"]
    cross = centre[None, :, 0] * velocity[:, :, 1] - centre[None, :, 1] * velocity[:, :, 0]
    moment = np.einsum("b,fb->f", data["mass"], cross) + omega[:, :, 2] @ inertia
    before = data["summary"]["angular_momentum"]["before"][0]
    np.testing.assert_allclose(moment, before, rtol=0, atol=1e-12 * abs(before))
    packing_output.write_paraview(out)
    beads = meshio.read(out / "paraview" / f"beads_{frames - 1:04d}.vtu")
    np.testing.assert_array_equal(beads.point_data["angular_velocity"], omega[-1])
    # drawn with the beads coloured by their spin: both senses show, blue and red
    if shutil.which("xvfb-run") is None:
        return
    png = tmp_path / "spins.png"
    subprocess.run(["xvfb-run", "-a", sys.executable, "-c",
                    f"from mimpact import packing_output; packing_output.render("
                    f"{str(out)!r}, {str(png)!r}, frame=-1, spins=True)"],
                   check=True, env=dict(os.environ), capture_output=True)
    pixels = matplotlib.image.imread(png)[:, :, :3]
    red = (pixels[:, :, 0] > 0.6) & (pixels[:, :, 2] < 0.35)
    blue = (pixels[:, :, 2] > 0.6) & (pixels[:, :, 0] < 0.4)
    assert red.sum() > 300 and blue.sum() > 300
