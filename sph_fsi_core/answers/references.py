"""Analytic and experimental references the scenes are judged against.

Data files live in `reference_data/` (copies of the project's shared reference set, each with its source in its
header; test_scene.py checks the copies against the originals when those are present), and one table the project
computes itself, cantilever_fe3d_nondimensional.csv (its header says how).
"""
import csv
import io
import math
from functools import lru_cache
from pathlib import Path

DATA_DIR = Path(__file__).resolve().parent / "reference_data"


def read_reference_table(name):
    """Rows of a reference CSV as dicts of strings, skipping '#' comment lines (tables of names and notes)."""
    lines = [ln for ln in (DATA_DIR / name).read_text().splitlines() if not ln.startswith("#")]
    return list(csv.DictReader(io.StringIO("\n".join(lines))))


def read_reference_csv(name):
    """Rows of a reference CSV as dicts of floats (empty cells: None), skipping '#' comment lines."""
    return [{k: (float(v) if v not in ("", None) else None) for k, v in row.items()}
            for row in read_reference_table(name)]


@lru_cache(maxsize=None)
def clamped_free_mode_kl(mode=1):
    """Root k L of cos(kL) cosh(kL) = -1, eq. (14) (first mode: 1.87510...), by Newton from the asymptote."""
    x = (mode - 0.5) * math.pi if mode > 1 else 1.875
    for _ in range(50):
        g = math.cos(x) * math.cosh(x) + 1.0
        dg = -math.sin(x) * math.cosh(x) + math.cos(x) * math.sinh(x)
        step = g / dg
        x -= step
        if abs(step) < 1e-15:
            break
    return x


def cantilever_mode_velocity(x, length, tip_velocity):
    """Eqs. (12)-(13): the first bending mode's velocity profile along the beam, equal to tip_velocity at x = L."""
    import numpy as np
    kl = clamped_free_mode_kl(1)
    k = kl / length
    m = math.sin(kl) + math.sinh(kl)
    n = math.cos(kl) + math.cosh(kl)
    q = 2.0 * (math.cos(kl) * math.sinh(kl) - math.sin(kl) * math.cosh(kl))
    kx = k * np.asarray(x)
    return tip_velocity / q * (m * (np.cos(kx) - np.cosh(kx)) - n * (np.sin(kx) - np.sinh(kx)))


def beam_theory_frequency(length, thickness, young_modulus, density):
    """Euler-Bernoulli first bending mode of a clamped-free beam: f = (k^2 / 2 pi) H sqrt(E / (12 rho))."""
    k = clamped_free_mode_kl(1) / length
    return k * k / (2.0 * math.pi) * thickness * math.sqrt(young_modulus / (12.0 * density))


def plate_frequency_eq15(length, thickness, young_modulus, poisson_ratio, density):
    """Satake et al. eq. (15), the plane-strain plate formula: f = H k^2 / (4 pi) sqrt(E / (3 rho (1 - nu^2)))."""
    k = clamped_free_mode_kl(1) / length
    return thickness * k * k / (4.0 * math.pi) * math.sqrt(
        young_modulus / (3.0 * density * (1.0 - poisson_ratio ** 2)))


# The geometry and material of reference_data/cantilever_frequencies.csv (its header).
_FE_TABLE_CASE = dict(thickness=0.004, width=0.006, young_modulus=1.859e6, poisson_ratio=0.49, density=1000.0)

# The project's 3D FE for other shapes and Poisson ratios, as f H / sqrt(E / rho) (cantilever_fe_table.py writes
# it); shapes it does not list are computed on demand and kept in FE3D_CACHE_FILE under the user's cache directory.
FE3D_TABLE = "cantilever_fe3d_nondimensional.csv"
FE3D_TABLE_COLUMNS = ("length_over_thickness", "width_over_thickness", "poisson_ratio", "frequency_nondimensional",
                      "order", "mesh_frequencies")
FE3D_CACHE_FILE = "cantilever_fe3d_nondimensional.csv"


def format_fe3d_row(length_over_thickness, width_over_thickness, poisson_ratio, result):
    """One line of the nondimensional table from a fe_reference.cantilever_fe_nondimensional result."""
    meshes = " ".join(f"{f:.10g}" for f in result["mesh_frequencies"])
    return (f"{length_over_thickness:.10g},{width_over_thickness:.10g},{poisson_ratio:.10g},"
            f"{result['frequency']:.10g},{result['order']:.4g},{meshes}")


def fe3d_cache_dir():
    """$SPH_FSI_CACHE, else $XDG_CACHE_HOME/sph_fsi, else ~/.cache/sph_fsi."""
    import os
    if os.environ.get("SPH_FSI_CACHE"):
        return Path(os.environ["SPH_FSI_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "sph_fsi"


def _nondimensional_rows(path):
    if not path.is_file():
        return []
    lines = [ln for ln in path.read_text().splitlines() if ln.strip() and not ln.startswith("#")]
    rows = []
    for row in csv.DictReader(io.StringIO("\n".join(lines))):
        rows.append((float(row["length_over_thickness"]), float(row["width_over_thickness"]),
                     float(row["poisson_ratio"]), float(row["frequency_nondimensional"])))
    return rows


def _lookup(rows, shape):
    for *key, value in rows:
        if all(abs(k - s) <= 1e-9 * max(1.0, abs(s)) for k, s in zip(key, shape)):
            return value
    return None


def fe3d_frequency(length, thickness, width, young_modulus, poisson_ratio, density, compute=True):
    """3D linear-elasticity first vertical bending frequency of the clamped-free beam (Hz) and its source, or
    (None, why).

    In order: the paper's beam from cantilever_frequencies.csv (its mesh-extrapolated value, as published); the
    project's nondimensional table (FE3D_TABLE, extrapolated meshes H/2, H/4, H/6); the user's cache; else, with
    `compute`, cantilever_fe_nondimensional now (seconds to minutes, scikit-fem and scipy), kept in the cache.
    Frequencies of a linear elastic body scale exactly as sqrt(E / rho) / H at fixed shape and nu.
    """
    scale = math.sqrt(young_modulus / density) / thickness
    paper = (abs(thickness - _FE_TABLE_CASE["thickness"]) < 1e-9 and abs(width - _FE_TABLE_CASE["width"]) < 1e-9
             and abs(poisson_ratio - _FE_TABLE_CASE["poisson_ratio"]) < 1e-9)
    if paper:
        for row in read_reference_csv("cantilever_frequencies.csv"):
            if abs(row["L_mm"] * 1e-3 - length) < 1e-9 and row["fe3d_extrapolated_Hz"] is not None:
                ratio = math.sqrt((young_modulus / density)
                                  / (_FE_TABLE_CASE["young_modulus"] / _FE_TABLE_CASE["density"]))
                return row["fe3d_extrapolated_Hz"] * ratio, "fe3d_extrapolated"
    shape = (length / thickness, width / thickness, poisson_ratio)
    value = _lookup(_nondimensional_rows(DATA_DIR / FE3D_TABLE), shape)
    if value is not None:
        return value * scale, "fe3d_extrapolated"
    cache = fe3d_cache_dir() / FE3D_CACHE_FILE
    value = _lookup(_nondimensional_rows(cache), shape)
    if value is not None:
        return value * scale, "fe3d_extrapolated (computed, cached)"
    if not compute:
        return None, "no 3D reference for this shape and Poisson ratio (not computed)"
    try:
        from .fe_reference import cantilever_fe_nondimensional
        result = cantilever_fe_nondimensional(*shape)
    except (ImportError, ValueError) as exc:
        return None, f"no 3D reference: {exc}"
    cache.parent.mkdir(parents=True, exist_ok=True)
    if not cache.is_file():
        cache.write_text(f"# {FE3D_TABLE}'s columns, computed on demand by sph_fsi\n"
                         + ",".join(FE3D_TABLE_COLUMNS) + "\n")
    with cache.open("a") as fh:
        fh.write(format_fe3d_row(*shape, result) + "\n")
    return result["frequency"] * scale, "fe3d_extrapolated (computed)"


def cantilever_references(length, thickness, width, young_modulus, poisson_ratio, density):
    """All three references for the cantilever's first vertical mode and which one judges the run."""
    fe, label = fe3d_frequency(length, thickness, width, young_modulus, poisson_ratio, density)
    eb = beam_theory_frequency(length, thickness, young_modulus, density)
    eq15 = plate_frequency_eq15(length, thickness, young_modulus, poisson_ratio, density)
    judged = ("fe3d", fe, label) if fe is not None else ("euler_bernoulli", eb, label)
    return {"fe3d_hz": fe, "fe3d_source": label, "euler_bernoulli_hz": eb, "eq15_hz": eq15,
            "judged_against": judged[0], "reference_hz": judged[1]}


def _front_table(name):
    """(T, Z) columns of a surge-front reference CSV, as arrays."""
    import numpy as np
    rows = read_reference_csv(name)
    return np.array([r["T"] for r in rows]), np.array([r["Z"] for r in rows])


def martin_moyce_front():
    """(T, Z) of Martin & Moyce 1952, Fig. 3 (reference_data/martin_moyce_1952_a57mm.csv): surge-front position
    Z = x_front / a against T = t sqrt(2 g / a) for a column of height 2a, a = 57.15 mm."""
    return _front_table("martin_moyce_1952_a57mm.csv")


def antoci_gate_tip(component):
    """(t [s], displacement [m]) of the gate's free end measured by Antoci, Gallati & Sibilla 2007
    (reference_data/antoci2007_exp_gate_tip_x.csv for 'x'; _y.csv, their vertical, for 'z'); digitised, not
    zero-shifted."""
    import numpy as np
    name, col = {"x": ("antoci2007_exp_gate_tip_x.csv", "x_m"),
                 "z": ("antoci2007_exp_gate_tip_y.csv", "y_m")}[component]
    rows = read_reference_csv(name)
    return np.array([r["time_s"] for r in rows]), np.array([r[col] for r in rows])


def _elastica_shoot(alpha, curvature0, steps, distributed=False):
    """theta'' = -alpha w(s) cos(theta) from the clamp (theta = 0, theta' = curvature0) along s in [0, 1] (RK4),
    w = 1 (a tip load) or 1 - s (a distributed load); returns theta(1), theta'(1), and the integrals of sin(theta)
    and cos(theta) (Simpson)."""
    h = 1.0 / steps
    theta, kappa = 0.0, curvature0
    sines, cosines = [0.0], [1.0]
    w = (lambda s: 1.0 - s) if distributed else (lambda s: 1.0)   # noqa: E731
    for i in range(steps):
        s0 = i * h
        k1t, k1k = kappa, -alpha * w(s0) * math.cos(theta)
        k2t, k2k = kappa + 0.5 * h * k1k, -alpha * w(s0 + 0.5 * h) * math.cos(theta + 0.5 * h * k1t)
        k3t, k3k = kappa + 0.5 * h * k2k, -alpha * w(s0 + 0.5 * h) * math.cos(theta + 0.5 * h * k2t)
        k4t, k4k = kappa + h * k3k, -alpha * w(s0 + h) * math.cos(theta + h * k3t)
        theta += h / 6.0 * (k1t + 2 * k2t + 2 * k3t + k4t)
        kappa += h / 6.0 * (k1k + 2 * k2k + 2 * k3k + k4k)
        sines.append(math.sin(theta))
        cosines.append(math.cos(theta))
    weights = [1.0] + [4.0 if i % 2 else 2.0 for i in range(1, steps)] + [1.0]
    integral = lambda values: h / 3.0 * sum(w * v for w, v in zip(weights, values))   # noqa: E731
    return theta, kappa, integral(sines), integral(cosines)


@lru_cache(maxsize=64)
def elastica_tip(alpha, steps=2000, distributed=False):
    """A cantilever (clamped at s = 0, free at s = L) under a dead load P across its axis at the free end, with
    exact rotation (Euler-Bernoulli, inextensible, no shear): EI theta'' = -P cos(theta), theta(0) = 0, theta'(L) =
    0; alpha = P L^2 / (E I). Returns {deflection, pull_back (1 - x_tip / L), rotation (rad)} of the free end, over
    L. Solved here by shooting on the clamp's curvature (bisection on [0, alpha], RK4 with `steps` steps); Bisshopp
    & Drucker 1945 (Q. Appl. Math. 3, 272) tabulate alpha = 1: 0.3017, 0.0566 (test_cantilever_loaded.py checks).
    distributed: a dead load q per length along the beam instead, EI theta'' = -q (L - s) cos(theta), alpha =
    q L^3 / (E I) (small alpha: deflection alpha / 8)."""
    if alpha <= 0.0:
        return {"deflection": 0.0, "pull_back": 0.0, "rotation": 0.0}
    lo, hi = 0.0, alpha          # theta'(0) = P x_tip / (E I) <= alpha
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _elastica_shoot(alpha, mid, 200, distributed)[1] > 0.0:   # moment left at the free end: too much curvature
            hi = mid
        else:
            lo = mid
    # refine on the fine grid around the coarse root
    lo, hi = 0.98 * lo, min(alpha, 1.02 * hi + 1e-12)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _elastica_shoot(alpha, mid, steps, distributed)[1] > 0.0:
            hi = mid
        else:
            lo = mid
    theta, _, sin_integral, cos_integral = _elastica_shoot(alpha, 0.5 * (lo + hi), steps, distributed)
    return {"deflection": sin_integral, "pull_back": 1.0 - cos_integral, "rotation": theta}


def lobovsky_front():
    """(T, Z) of Lobovsky et al. 2014, Fig. 12, H = L = 600 mm (reference_data/lobovsky2014_front_H600.csv): the
    surge front Z = 1 + x / H, x from the gate, against T = t sqrt(g / H), t from the gate's first motion (lifted
    at a median 4.53 m/s). The last three points sit at the far wall (Z = 2.683)."""
    return _front_table("lobovsky2014_front_H600.csv")
