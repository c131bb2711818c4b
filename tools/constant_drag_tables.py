"""Built-in aerodynamic tables with a constant drag coefficient in place of the drag build-up.

Reads the tables a `source = builtin` run wrote (`OUT/aero_tables/body.csv` and `fins.csv`,
docs/outputs.md) and writes them again with the body table's `ca` set to CD at every row and
the fin table's `ca` set to 0: the built-in normal force, moment and rate columns unchanged,
the whole axial force a constant C_D on the reference area, whatever the Mach number and the
angle of attack (as RocketPy flies a constant `power_off_drag` / `power_on_drag`), against
the flow: -CD where the air comes from behind (|alpha| > 90 deg; the built-in tables span
every flow direction) and 0 at 90 deg. Fly them
with `aero { source = tables; body_table = ...; fin_table = ... }` and the same reference
length and point.

Used for examples/ndrt2020 (the team's C_D 0.44):
    python3 tools/constant_drag_tables.py OUT/aero_tables 0.44 examples/ndrt2020/ndrt2020_cd044

Usage: python3 constant_drag_tables.py TABLES_DIR CD OUT_PREFIX  (writes PREFIX_body.csv,
PREFIX_fins.csv)
"""

import sys


def rewrite(src, dst, cd, note):
    with open(src) as fh:
        lines = fh.read().splitlines()
    out = [f"# {note}"]
    col = None
    for line in lines:
        if line.startswith("#"):
            out.append(line)
            continue
        cells = line.split(",")
        if col is None:
            col = cells.index("ca")
            alpha = cells.index("alpha_deg")
            out.append(line)
            continue
        a = abs(float(cells[alpha]))
        cells[col] = repr(cd if a < 90.0 else (0.0 if a == 90.0 else -cd))
        out.append(",".join(cells))
    with open(dst, "w") as fh:
        fh.write("\n".join(out) + "\n")


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    tables, cd, prefix = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    rewrite(f"{tables}/body.csv", f"{prefix}_body.csv", cd,
            f"tools/constant_drag_tables.py: ca = {cd} against the flow at every row (the built-in drag replaced)")
    rewrite(f"{tables}/fins.csv", f"{prefix}_fins.csv", 0.0,
            "tools/constant_drag_tables.py: ca = 0 at every row (all of the drag in the body table)")


if __name__ == "__main__":
    main()
