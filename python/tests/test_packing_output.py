"""`mimpact packing --out` read back, written for ParaView with meshio, and drawn."""

import subprocess
import xml.etree.ElementTree as ElementTree

import meshio
import numpy as np

from conftest import SOURCE
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

    collection = packing_output.write_paraview(out)
    datasets = ElementTree.parse(collection).getroot().find("Collection")
    assert len(datasets) == 2 * frames
    last = frames - 1
    beads = meshio.read(out / "paraview" / f"beads_{last:04d}.vtu")
    assert len(beads.points) == 101
    np.testing.assert_array_equal(beads.point_data["radius"], data["radius"])
    np.testing.assert_array_equal(beads.point_data["velocity"][:, :2], data["velocity"][last])
    contacts = meshio.read(out / "paraview" / f"contacts_{last:04d}.vtu")
    assert contacts.cells[0].data.shape == (262, 2)
    np.testing.assert_array_equal(contacts.cell_data["force"][0], data["force"][last])
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
