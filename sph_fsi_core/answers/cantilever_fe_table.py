"""Writes reference_data/cantilever_fe3d_nondimensional.csv: the project's 3D FE first vertical bending frequency of
a clamped-free beam, f H / sqrt(E / rho), for the shapes and Poisson ratios the validation cases run
(fe_reference.cantilever_fe_nondimensional; a few minutes on one core).

    python -m sph_fsi_core.answers.cantilever_fe_table

Any other shape is computed when a run needs it and kept in the user's cache (references.fe3d_frequency).
"""
import sys
import time

from .fe_reference import CANTILEVER_FE_DIVISIONS, cantilever_fe_nondimensional
from .references import DATA_DIR, FE3D_TABLE, FE3D_TABLE_COLUMNS, format_fe3d_row

# The paper's cross-section (W / H = 6 / 4), Poisson ratios 0.3, 0.4 and 0.49, L / H from 10 to 30.
WIDTH_OVER_THICKNESS = 1.5
POISSON_RATIOS = (0.3, 0.4, 0.49)
LENGTHS_OVER_THICKNESS = (10.0, 15.0, 20.0, 25.0, 30.0)


def main():
    header = ("# The project's 3D FE: first vertical bending frequency of a beam L x W x H clamped on its whole x = 0 "
              "face, as f H / sqrt(E / rho); scikit-fem, triquadratic hexahedra of H/"
              + ", H/".join(str(n) for n in CANTILEVER_FE_DIVISIONS)
              + ", extrapolated to zero size (sph_fsi_core/answers/fe_reference.py, cantilever_fe_nondimensional). "
              "Made by: python -m sph_fsi_core.answers.cantilever_fe_table")
    lines = [header, ",".join(FE3D_TABLE_COLUMNS)]
    for nu in POISSON_RATIOS:
        for ratio in LENGTHS_OVER_THICKNESS:
            t0 = time.perf_counter()
            result = cantilever_fe_nondimensional(ratio, WIDTH_OVER_THICKNESS, nu)
            lines.append(format_fe3d_row(ratio, WIDTH_OVER_THICKNESS, nu, result))
            print(f"L/H {ratio:g}, W/H {WIDTH_OVER_THICKNESS:g}, nu {nu:g}: {result['frequency']:.6g} "
                  f"(order {result['order']:.2f}, {time.perf_counter() - t0:.0f} s)", flush=True)
    (DATA_DIR / FE3D_TABLE).write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
