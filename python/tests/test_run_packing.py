"""run_packing(): the packings of `mimpact packing` from Python."""

import json
import subprocess
import warnings

import numpy as np
import pytest

import mimpact
from conftest import SOURCE, read_scene, rough_packing

HEXAGON = "examples/scenes/packings/hexagonal_10x10.json"


def test_run_packing_gives_the_command_lines_velocities(cli, tmp_path):
    result = mimpact.run_packing(SOURCE / HEXAGON)
    subprocess.run([cli, "packing", str(SOURCE / HEXAGON), "--out", str(tmp_path / "out"),
                    "--quiet"], check=True)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    np.testing.assert_array_equal(result.post_impact_velocities,
                                  np.array(summary["post_impact_velocities"]))
    assert result.post_impact_velocities.shape == (101, 2)
    assert result.contact_bodies.shape == (262, 2)
    # the impulses the bodies received sum to zero: momentum is kept to round-off
    momentum = result.body_impulses.sum(axis=0)
    np.testing.assert_allclose(momentum, 0.0, atol=1e-15)
    assert result.frames["velocities"].shape[1:] == (101, 2)


def test_the_frozen_configuration_is_told():
    """Issue 24, item e: an LZB run of beads warns that its configuration of the impact is 5 % of
    V from the beads as they move, as the command line does; a scene may skip the check."""
    with pytest.warns(UserWarning, match='the scene needs "method": "compliant"'):
        result = mimpact.run_packing(SOURCE / HEXAGON)
    check = result.summary["configuration_check"]
    assert not check["holds"] and check["worst_error"] > 1e-2
    scene = read_scene(HEXAGON)
    scene["configuration_check"] = {"enabled": False}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert mimpact.run_packing(scene).summary["configuration_check"] is None


def test_a_dict_scene_and_delta_p(tmp_path):
    scene = read_scene(HEXAGON)
    scene["impact"] = {"delta_p": 1e-5}
    scene.pop("record")
    coarse = mimpact.run_packing(scene)
    fine = mimpact.run_packing(scene, delta_p=2.5e-6)
    assert coarse.delta_p == 1e-5 and fine.delta_p == 2.5e-6
    adaptive = mimpact.run_packing(read_scene(HEXAGON))
    # first order: a quarter of the step, about a quarter of the error
    coarse_error = abs(coarse.post_impact_velocities - adaptive.post_impact_velocities).max()
    fine_error = abs(fine.post_impact_velocities - adaptive.post_impact_velocities).max()
    assert 3.0 < coarse_error / fine_error < 5.0
    # the work of a step: the LZB integrators count contacts, the compliant contacts bodies
    assert coarse.contacts_per_step > 0.0
    scene["method"] = "compliant"
    scene.pop("impact")
    compliant = mimpact.run_packing(scene)
    assert compliant.contacts_per_step is None
    assert compliant.summary["moving_geometry"]["body_steps"] > 0


def test_bad_input_is_a_value_error_naming_the_field():
    scene = read_scene(HEXAGON)
    scene["strikers"][0]["target"] = [0, 12]
    with pytest.raises(ValueError, match=r"strikers\[0\]\.target\[1\] = 12 is invalid"):
        mimpact.run_packing(scene)
    with pytest.raises(ValueError, match="scene = 3 is not allowed"):
        mimpact.run_packing(3)


def _fcc(**striker):
    scene = {"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
             "lattice": {"type": "fcc", "layers": 2, "rows": 2, "columns": 2, "radius": 0.005},
             "strikers": [{"target": [0, 0, 0], "radius": 0.005, "velocity": [0, 0, 1]}],
             "impact": {"delta_p": 1e-5}}
    scene["strikers"][0].update(striker)
    return scene


def test_three_dimensional_packings_and_their_bad_input(tmp_path):
    result = mimpact.run_packing(_fcc())
    assert result.post_impact_velocities.shape == (9, 3)
    np.testing.assert_allclose(result.body_impulses.sum(axis=0), 0.0, atol=1e-15)
    # issue 24, item f: one clear error each
    with pytest.raises(ValueError, match=r"strikers\[0\]\.velocity = \[0, 1\] has 2 components; "
                                         r"allowed: 3 in a three-dimensional packing"):
        mimpact.run_packing(_fcc(velocity=[0, 1]))
    walled = read_scene(HEXAGON)
    walled["walls"] = [{"point": [0, -0.005], "normal": [0, 0]}]
    with pytest.raises(ValueError, match=r"walls\[0\]\.normal = \[0, 0\] is invalid; allowed: a "
                                         r"normal of length > 0"):
        mimpact.run_packing(walled)
    (tmp_path / "beads.csv").write_text("x,y,z,radius\n0,0,0,0.005\n0.009,0,0,0.005\n")
    listed = {"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
              "beads": {"file": "beads.csv"},
              "strikers": [{"target": [0], "radius": 0.005, "velocity": [1, 0, 0]}]}
    with pytest.raises(ValueError, match=r"lines 2 and 3: bead 0 and bead 1 overlap by 0\.001"):
        mimpact.run_packing(listed, data_dir=tmp_path)


def test_a_spinning_striker_on_a_rough_packing():
    """Issue 46: a striker that comes off-centre and spinning on a rough hexagonal packing; the
    angular velocities as summary.json has them, momentum and angular momentum about the origin
    kept to round-off, the kinetic energy lost to the normal and slip work."""
    result = mimpact.run_packing(rough_packing())
    summary = result.summary
    spins = result.post_impact_angular_velocities
    assert spins.shape == (17, 1)
    np.testing.assert_array_equal(spins[:, 0], summary["post_impact_angular_velocities"])
    assert np.count_nonzero(spins[:16]) > 4  # the packing's beads were set turning
    moment = summary["angular_momentum"]
    scale = 1e-2 * np.linalg.norm(summary["momentum"]["before"])  # m V (2 R)
    np.testing.assert_allclose(moment["after"], moment["before"], rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(summary["momentum"]["after"], summary["momentum"]["before"],
                               rtol=0, atol=1e-12 * np.linalg.norm(summary["momentum"]["before"]))
    energy = summary["energy"]
    before = energy["kinetic_before"] + energy["rotational_before"]
    after = energy["kinetic_after"] + energy["rotational_after"]
    assert energy["slip_total"] > 0
    assert before - after == pytest.approx(energy["dissipated_total"], rel=1e-10)
    rubbing = [c for c in summary["contacts"] if "tangential_impulse" in c]
    assert len(rubbing) == len(summary["contacts"])


def test_the_compliant_contacts_rub_in_the_frozen_configuration():
    """Issue 46: the compliant contacts with Coulomb's law, rigid across the contact, in the
    frozen configuration (compliant.geometry "frozen") meet the adaptive LZB impact at e = 1
    and give the same outputs. In the moving geometry the contacts rub through Mindlin's
    tangential spring (LAMMPS's model): its energy ledger balances; it refuses an inelastic
    law with friction, naming the field."""
    scene = rough_packing()
    scene["contact"]["restitution"] = 1.0
    scene["impact"]["tolerance"] = 1e-12
    lzb = mimpact.run_packing(scene)
    del scene["impact"]
    scene["method"] = "compliant"
    scene["compliant"] = {"tolerance": 1e-12, "geometry": "frozen", "gaps": "frozen"}
    compliant = mimpact.run_packing(scene)
    np.testing.assert_allclose(compliant.post_impact_velocities, lzb.post_impact_velocities,
                               rtol=0, atol=1e-10)
    np.testing.assert_allclose(0.005 * compliant.post_impact_angular_velocities,
                               0.005 * lzb.post_impact_angular_velocities, rtol=0, atol=1e-10)
    energy, lzb_energy = compliant.summary["energy"], lzb.summary["energy"]
    assert energy["dissipated_total"] == pytest.approx(lzb_energy["dissipated_total"], rel=1e-10)
    # each method releases a contact at its own resolution of the overlap, where the normal law
    # keeps about 1e-9 J of 2.5e-3 J (e = 1): the slip's share agrees to that
    assert energy["slip_total"] == pytest.approx(lzb_energy["slip_total"], rel=1e-5)
    # the steps across the springs' switches are amended, no longer shortened by each: the
    # ledger closes to the Dormand-Prince steps' own accuracy, 1.2e-9 at tolerance 1e-10 and
    # 1.5e-10 at 1e-11 (as without friction through the same steps)
    scene["compliant"] = {"geometry": "moving", "tolerance": 1e-11}
    moving = mimpact.run_packing(scene).summary["energy"]
    before = moving["kinetic_before"] + moving["rotational_before"]
    lost = before - moving["kinetic_after"] - moving["rotational_after"]
    assert moving["slip_total"] > 0.01 * lost
    assert lost == pytest.approx(moving["dissipated_total"] + moving["potential_left"],
                                 abs=1e-9 * before)
    scene["contact"]["restitution"] = 0.9
    with pytest.raises(ValueError, match=r"contact\.restitution = 0\.9.*moving geometry"):
        mimpact.run_packing(scene)


def test_the_ledger_counts_the_contacts_the_bodies_form():
    """In the moving geometry a contact that forms as the bodies move is in the ledger: a 5 um
    striker, spinning, bounces off a rough 3 x 4 hexagonal packing and then off the left wall,
    a contact the model did not have, which takes 1.4 % of the energy by its slip. The ledger
    closes to the steps' accuracy (8e-7 at tolerance 1e-7; 1.4e-2 without that contact)."""
    scene = {"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
             "lattice": {"type": "hexagonal", "rows": 3, "columns": 4, "radius": 0.005},
             "walls": [{"side": "left"}],
             "strikers": [{"target": [0, 2], "radius": 5e-06, "velocity": [0.3, 1.0],
                           "offset": 0.002, "spin": -100}],
             "contact": {"restitution": 1.0, "friction": 0.3}, "method": "compliant",
             "compliant": {"tolerance": 1e-07, "geometry": "moving", "end_time": 0.03}}
    energy = mimpact.run_packing(scene).summary["energy"]
    before = energy["kinetic_before"] + energy["rotational_before"]
    after = (energy["kinetic_after"] + energy["rotational_after"] + energy["dissipated_total"]
             + energy["potential_left"])
    formed = energy["formed_contacts"]
    assert formed["count"] == 1
    assert formed["dissipated"] > 0.01 * before
    assert after == pytest.approx(before, rel=1e-5)
    assert energy["dissipated_total"] == pytest.approx(
        sum(energy["dissipated"]) + formed["dissipated"], rel=1e-12)
