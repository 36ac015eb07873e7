#!/usr/bin/python3
"""Writes the papers' numbers into docs/experiments.md from the one file that holds them,
examples/scenes/paper/published.json, which the tests and scripts/reproduce_paper.py read too.

Each block of published numbers in the page stands between two markers,

    <!-- published: SET -->
    ...
    <!-- end published -->

and is rewritten from the set SET of the file, its source last. With --check nothing is
written: the script lists the blocks that differ from the file and exits 1 (a CTest test runs
it so).

    /usr/bin/python3 scripts/published_tables.py [--check]
"""
import argparse
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PUBLISHED = ROOT / "examples" / "scenes" / "paper" / "published.json"
PAGE = ROOT / "docs" / "experiments.md"
BLOCK = re.compile(r"(<!-- published: (\w+) -->\n)(.*?)(<!-- end published -->)", re.S)


def number(value):
    """A published number as the papers print it: 1e-5 rather than 1e-05, '—' for none."""
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int):
        return str(value)
    text = f"{value:g}"
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("-" if m[1] == "-" else "") + m[2], text)


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def power_of_ten(value):
    """A step as the papers write it: 1e-4."""
    mantissa, exponent = f"{value:e}".split("e")
    return f"{float(mantissa):g}e{int(exponent)}"


def convergence(block):
    rows = [[chain, power_of_ten(row[0]), f"{row[1]:,}".replace(",", " ")] +
            [number(value) for value in row[2:]]
            for chain in ("C1", "C2", "C3") for row in block[chain]]
    return table(["chain", "ΔP (N·s)", "steps", "max η_h", "η⁺_h", "converged (ε = ε⁺ = 0.01)",
                  "time (s, 2011 PC)"], rows)


def wall_scaling(block):
    return table(["e_s", "F_wall / F_chain", "τ_wall / τ_chain", "T_wall / T_chain"],
                 [[number(row[0])] + [f"≈ {number(v)}" for v in row[1:]] for row in block["rows"]])


def wall_extrapolation(block):
    force, width = number(block["force"]), number(block["width"])
    return (f"`F_chain = F_wall / {force}`, `τ_chain = τ_wall / {width}`, hence "
            f"`P_chain = P_wall / ({width} × {force})` for both `P_F` and `P_T` (eqs. 44–45).")


QUANTITIES = {
    "interface_over_incident": "interface / incident amplitude",
    "interface_force": "interface amplitude (N)",
    "waves_in_first_train": "significant solitary waves in the first train (25 small beads)",
    "single_wave_force_bead_9": "F_m at bead 9, single wave (N)",
    "single_wave_force_bead_17": "F_m at bead 17, single wave (N)",
    "delay_at_bead_17_us": "delay of the left wave at bead 17 after the collision (µs)",
    "left_wave_force_at_bead_17_after": "left wave at bead 17 after the collision (N)",
    "secondary_wave_force": "secondary solitary waves (N)",
}


def simulated_and_measured(block, first, label):
    """A table of rows (first column, quantity, simulated, measured); a value the paper gives as
    approximate (listed under "approximate") is printed so."""
    approximate = [tuple(entry) for entry in block.get("approximate", [])]

    def value(key, quantity, column, v):
        return ("about " if (key, quantity, column) in approximate else "") + number(v)

    return table([first, "quantity", "Nguyen & Brogliato's simulation", "experiment"],
                 [[label(key), QUANTITIES[q], value(key, q, "simulated", s), value(key, q, "measured", m)]
                  for key, q, s, m in block["rows"]])


def stepped_chain(block):
    return simulated_and_measured(block, "e_s", number)


def colliding_waves(block):
    return simulated_and_measured(block, "chain", lambda beads: f"{beads} beads")


def solitary_wave_speed(block):
    beads, constants = block["beads"], block["table_I"]
    pairs = lambda points: " ".join(f"({number(f)}, {number(v)})" for f, v in points)  # noqa: E731
    lines = [f"- The beads (table I): `a = {number(beads['radius'])} m`, `E = {number(beads['young'])} Pa`, "
             f"`ν = {number(beads['poisson'])}`, `ρ = {number(beads['density'])} kg/m³`; "
             f"`θ = {number(constants['theta'])} m²/N`, `C = {number(constants['C'])} m/s`, "
             f"a bead's mass `{number(constants['bead_mass'])} kg`.",
             f"- `F_0 = 0` (figures 13–15), (`F_m` in N, `V` in m/s): {pairs(block['static_force_0'])}."]
    for static, figure in block["precompressed"].items():
        ratios = ", ".join(number(r) for r in figure["strain_ratios"])
        lines.append(f"- `F_0 = {static} N`: {pairs(figure['pairs'])}; strain ratios `ψ_m/ψ_∞` {ratios}.")
    lines.append(f"- Figure 12b: `V/c_s = k [y_∞(F_m/F_0)]^(−1/5)` fitted to the measured points gives "
                 f"`k = {number(block['fitted_k'])}`.")
    return "\n".join(lines)


def siconos_c1(block):
    velocities = block["velocities"]
    signed = [("−" + number(-v)) if v < 0 else number(v) for v in velocities]
    rows = [" ".join(signed[k:k + 8])
            for k in range(0, len(signed), 8)]
    return "\n".join("    " + row for row in rows)


RENDER = {"convergence": convergence, "siconos_c1": siconos_c1, "wall_scaling": wall_scaling,
          "wall_extrapolation": wall_extrapolation, "stepped_chain": stepped_chain,
          "colliding_waves": colliding_waves, "solitary_wave_speed": solitary_wave_speed}


def rendered(page, published):
    """The page with every block rewritten, and the names of the sets found in it."""
    found = []

    def rewrite(match):
        name = match[2]
        if name not in RENDER:
            sys.exit(f"{PAGE}: no set '{name}' to write (allowed: {', '.join(RENDER)})")
        found.append(name)
        body = RENDER[name](published[name])
        return f"{match[1]}{body}\n\nSource: {published[name]['source']}.\n{match[4]}"

    return BLOCK.sub(rewrite, page), found


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--check", action="store_true", help="only check that the page is current")
    args = parser.parse_args()
    published = json.loads(PUBLISHED.read_text())
    page = PAGE.read_text()
    new, found = rendered(page, published)
    missing = sorted(set(published) - set(found) - {"about"})
    if missing:
        sys.exit(f"{PAGE}: no block for the published set(s) {', '.join(missing)}")
    if args.check:
        stale = [m[2] for m, n in zip(BLOCK.finditer(page), BLOCK.finditer(new)) if m[0] != n[0]]
        if stale:
            sys.exit(f"{PAGE}: the block(s) {', '.join(stale)} differ from {PUBLISHED.name}; "
                     f"run /usr/bin/python3 scripts/published_tables.py")
        print(f"{PAGE.name}: {len(found)} blocks, all as {PUBLISHED.name} gives them")
        return
    PAGE.write_text(new)
    print(f"wrote {len(found)} blocks into {PAGE}")


if __name__ == "__main__":
    main()
