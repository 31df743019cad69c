"""Every scene key, declared once: type, default, unit, range, description, and whether a change needs a rebuild.

The same declarations validate YAML scene files and `--set KEY=VALUE` overrides, generate `config/defaults.yaml`
and the docs' table of keys, and give the ROS node its parameter descriptors. A key belongs to a section; a
section belongs to a phase (solid, fluid, ...) or to every scene ('common'). A scene can only set keys of the
sections its builder has, so a cantilever file that mentions `fluid.*` is an error, not a silent no-op.
"""
import difflib
import math
from dataclasses import dataclass, field
from typing import Any

from .errors import SceneError
from .numerics.kernels import KERNELS
from .solid.schemes import DEFAULT_SCHEME, SCHEMES, expansion_text

MAX_ART_EXPONENT = 12   # solid.artificial_stress_exponent's upper bound (gray2001.integer_power takes n < 16)


@dataclass(frozen=True)
class Param:
    key: str
    default: Any
    unit: str
    description: str
    kind: str = "float"            # float | int | bool | str | vec3
    low: float | None = None
    high: float | None = None
    low_inclusive: bool = True
    high_inclusive: bool = True
    choices: tuple = ()
    rebuild: bool = True           # True: a change takes effect at the next reset (particles must be rebuilt)

    @property
    def section(self):
        return self.key.split(".", 1)[0]

    def range_text(self):
        if self.choices:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.low is None and self.high is None:
            return {"float": "a finite number", "int": "an integer", "bool": "true or false",
                    "str": "a string", "vec3": "a list of 3 finite numbers"}[self.kind]
        lo = "-inf" if self.low is None else f"{self.low:g}"
        hi = "inf" if self.high is None else f"{self.high:g}"
        left = "[" if self.low_inclusive and self.low is not None else "("
        right = "]" if self.high_inclusive and self.high is not None else ")"
        return f"in {left}{lo}, {hi}{right}" + (f" {self.unit}" if self.unit and self.unit != "1" else "")

    def _fail(self, value, why):
        raise SceneError(f"{self.key} = {value!r}: {why}; allowed: {self.range_text()}")

    def _check_number(self, value, x):
        if not math.isfinite(x):
            self._fail(value, "not finite")
        if self.low is not None and (x < self.low or (x == self.low and not self.low_inclusive)):
            self._fail(value, "out of range")
        if self.high is not None and (x > self.high or (x == self.high and not self.high_inclusive)):
            self._fail(value, "out of range")

    def coerce(self, value):
        """The value as this key's type, or SceneError naming the key and the allowed range."""
        if self.kind == "float":
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                self._fail(value, f"expected a number, got {type(value).__name__}")
            x = float(value)
            self._check_number(value, x)
            return x
        if self.kind == "int":
            if isinstance(value, bool) or not isinstance(value, int):
                if isinstance(value, float) and value.is_integer():
                    value = int(value)
                else:
                    self._fail(value, f"expected an integer, got {type(value).__name__}")
            self._check_number(value, value)
            return int(value)
        if self.kind == "bool":
            if not isinstance(value, bool):
                self._fail(value, f"expected true or false, got {type(value).__name__}")
            return value
        if self.kind == "str":
            if not isinstance(value, str):
                self._fail(value, f"expected a string, got {type(value).__name__}")
            if self.choices and value not in self.choices:
                self._fail(value, "not a known choice")
            return value
        if self.kind == "vec3":
            if not isinstance(value, (list, tuple)) or len(value) != 3:
                self._fail(value, "expected a list of 3 numbers")
            out = []
            for v in value:
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                    self._fail(value, "expected a list of 3 finite numbers")
                out.append(float(v))
            return tuple(out)
        raise AssertionError(self.kind)


def _p(*args, **kwargs):
    return Param(*args, **kwargs)


def _by_scheme(key):
    """A detailed key's default: the default scheme's value (solid/schemes.py), so the two cannot disagree."""
    return SCHEMES[DEFAULT_SCHEME].values[key]


_SET_BY_SCHEME = "; set by solid.scheme unless given explicitly (an explicit value overrides the scheme's)"


# Sections every scene has.
COMMON = [
    _p("scene.name", "", "", "Scene name, shown in outputs", kind="str", rebuild=False),
    _p("scene.builder", "", "", "Geometry builder that makes the particles", kind="str", rebuild=True),
    _p("scene.description", "", "", "One line on what the scene is", kind="str", rebuild=False),
    _p("scene.end_time", 0.2, "s", "Simulated time at which the run ends", low=0.0, low_inclusive=False,
       high=1.0e3, rebuild=False),
    _p("scene.gravity", (0.0, 0.0, 0.0), "m/s^2", "Body acceleration (z up; -9.81 in z for gravity)",
       kind="vec3", rebuild=False),
    _p("numerics.spacing", 1.0e-3, "m", "Initial particle spacing dp", low=1.0e-5, high=0.1),
    _p("numerics.smoothing_ratio", 1.3, "1", "Smoothing length over spacing, h / dp: the water's and the walls', "
       "and the solid's unless solid.smoothing_ratio gives its own", low=1.0, high=2.0),
    _p("numerics.neighbour_skin", 0.1, "1", "Verlet skin of the neighbour lists, as a fraction of h",
       low=0.0, low_inclusive=False, high=1.0),
    _p("output.timeseries_interval", 5.0e-4, "s", "Sampling interval of probes and energies (timeseries.csv)",
       low=1.0e-7, high=1.0, rebuild=False),
    _p("output.snapshot_format", "npz", "", "Snapshot files: 'npz' (NumPy arrays), 'vtk' (ParaView: .vtu per "
       "phase and a .pvd time series, sph_fsi_core/vtk_snapshots.py) or 'both'", kind="str",
       choices=("npz", "vtk", "both"), rebuild=False),
    _p("output.snapshot_interval", 0.01, "s", "Interval of particle snapshots (0: none)", low=0.0, high=10.0,
       rebuild=False),
    _p("watchdog.max_speed", 100.0, "m/s", "A moving particle faster than this stops the run as diverged",
       low=0.0, low_inclusive=False, rebuild=False),
    _p("watchdog.energy_growth", 2.0, "1",
       "Scenes with no energy input stop as diverged once kinetic + strain energy exceeds this multiple of "
       "its initial value", low=1.0, low_inclusive=False, rebuild=False),
    _p("watchdog.max_fluid_lost", 1.0, "1",
       "Water particles that leave the scene's domain (a splash over a wall) are held still where they left and "
       "recorded (how many, when, over which face of the domain box, nearest which wall: the log, summary.json's "
       "fluid_lost), and the run goes on: a splash is not a divergence. Below 1 the run stops once more than this "
       "fraction of the water has left (0: at the first), with status water_lost (exit status 4); 1: never",
       low=0.0, high=1.0, rebuild=False),
]

# The elastic solid (Gray et al. 2001; Satake et al. sec. 2.1).
SOLID = [
    _p("solid.density", 1000.0, "kg/m^3", "Reference density rho0 of the solid", low=1.0, high=1.0e5),
    _p("solid.smoothing_ratio", 0.0, "1",
       "The solid's own h / dp, 1 to 2 (0: numerics.smoothing_ratio, the water's and the walls'). The solid keeps the "
       "cubic spline whatever fluid.kernel is, and bends a thin plate further as its h grows (a plate 4 layers thick "
       "settles 4.95 % past FE at 1.3, 10.35 % at 2: docs/validation/studies/kernel), so a water kernel that wants "
       "a wider h need not take the solid there", low=0.0, high=2.0),
    _p("solid.young_modulus", 1.859e6, "Pa", "Young's modulus E", low=0.0, low_inclusive=False, high=1.0e13,
       rebuild=False),
    _p("solid.poisson_ratio", 0.49, "1", "Poisson's ratio nu (0.5 is incompressible and not allowed)", low=0.0,
       high=0.5, high_inclusive=False, rebuild=False),
    _p("solid.scheme", DEFAULT_SCHEME, "",
       "The solid's named scheme: one word for a validated combination of solid.velocity_gradient, "
       "solid.nodal_integration, solid.artificial_stress_epsilon, solid.cfl, solid.clamp, solid.pressure and "
       "solid.fit_refresh; each "
       "of those set "
       "explicitly "
       "overrides its scheme's value. "
       + "; ".join(f"'{s.name}' ({expansion_text(s.name)}): {s.summary}" for s in SCHEMES.values())
       + ". Which cases validated each, with which error: docs/method.md, 'Solid schemes'",
       kind="str", choices=tuple(SCHEMES)),
    _p("solid.cfl", _by_scheme("solid.cfl"), "1", "Solid time step dt = cfl * h / (c + |v|max), c the bulk sound "
       "speed c0 (or with solid.pressure = implicit the deviatoric waves' sqrt(4 G / 3 rho0))" + _SET_BY_SCHEME,
       low=0.0, low_inclusive=False, high=1.0, rebuild=False),
    _p("solid.time_step", 0.0, "s", "Forced solid time step (0: automatic); above the stable limit it is refused",
       low=0.0, high=1.0, rebuild=False),
    _p("solid.xsph_epsilon", 0.5, "1", "XSPH averaging eps of eq. (4)", low=0.0, high=1.0, rebuild=False),
    _p("solid.velocity_gradient", _by_scheme("solid.velocity_gradient"), "",
       "Velocity gradient behind Hooke's law and the pressure: 'sph' Gray 2001's sum (the paper), 'linear' the "
       "kernel-corrected L K^-1, 'quadratic' a quadratic least-squares fit (exact for bending at free surfaces; "
       "see docs/method.md)" + _SET_BY_SCHEME, kind="str", choices=("sph", "linear", "quadratic")),
    _p("solid.nodal_integration", _by_scheme("solid.nodal_integration"), "",
       "How the strain energy is summed over the particles: 'plain' with each particle's strain at its centre "
       "(SPH's nodal integration; a bent 4-layer beam is 6 % short in EI), 'gradient' plus the deviatoric strain's "
       "gradient across each particle's cell (exact for strain linear across a cell; needs "
       "solid.velocity_gradient = quadratic; costs about 2x per step; docs/method.md)" + _SET_BY_SCHEME, kind="str",
       choices=("plain", "gradient")),
    _p("solid.volumetric_gradient", False, "",
       "With solid.nodal_integration = gradient: the volumetric part of each cell's strain gradient too (its energy "
       "in full, not the deviator's only): the static plate 2.9x and the cantilever at L/H = 10 2.5-11x nearer FE at 4 "
       "particles through (docs/validation/linear_modes); the step shrinks with the bulk modulus (at nu = 0.49 "
       "2.4x more solid steps with the implicit pressure)", kind="bool"),
    _p("solid.fit_refresh_turn", 0.0, "1",
       "Quadratic fit: remake its moment rows once a particle's neighbourhood has turned or strained by this much "
       "(the integral of |L| dt) since they were made, besides at every neighbour-list build (0: only there, or "
       "1e-4 with solid.nodal_integration = gradient); a stale fit leaks rotation into the fitted curvature and "
       "locks energy in self-balanced stress (docs/method.md, 'Strain-gradient nodal integration')", low=0.0,
       high=1.0, rebuild=False),
    _p("solid.fit_refresh", _by_scheme("solid.fit_refresh"), "",
       "Quadratic fit: 'remake' its rows once a neighbourhood has turned or strained by solid.fit_refresh_turn (the "
       "integral of |L| dt); 'rotate' turn each particle's rows with its own rotation (exact for a rigid turn) every "
       "solid.fit_refresh_turn of it, and remake them once a neighbourhood's shape has changed by "
       "solid.fit_refresh_strain (a bending gate mostly turns, and vibrates in place: a tenth of the remakes; "
       "solid/fit_rotation.py)" + _SET_BY_SCHEME, kind="str", choices=("remake", "rotate")),
    _p("solid.fit_refresh_strain", 1.0e-3, "1",
       "solid.fit_refresh = rotate: remake the quadratic fit's rows once some neighbourhood's Green strain since they "
       "were made passes this (the rows are exact for the shape they were made at, turned)", low=0.0,
       low_inclusive=False, high=1.0, rebuild=False),
    _p("solid.clamp", _by_scheme("solid.clamp"), "",
       "How the clamp holds the body: 'fixed' clamp particles at rest carrying stress (the paper's; the body bends "
       "as if up to half a spacing longer), 'mirrored' clamp particles moving as the odd mirror image of the body "
       "across the clamp face, so the velocity vanishes on the face itself (small deflections near the clamp "
       "only; docs/method.md)" + _SET_BY_SCHEME, kind="str",
       choices=("fixed", "mirrored")),
    _p("solid.pressure", _by_scheme("solid.pressure"), "",
       "How the solid's pressure p = c0^2 (rho - rho0) advances: 'explicit' with the rest of eq. (5) (the step is "
       "set by the bulk sound speed c0), 'implicit' by backward Euler within each step (conjugate gradients), so the "
       "step is set by the deviatoric stress's waves, sqrt(4 G / 3 rho0): 6x larger at nu = 0.49 (needs "
       "solid.velocity_gradient = quadratic; solid/implicit_pressure.py, docs/method.md)" + _SET_BY_SCHEME,
       kind="str", choices=("explicit", "implicit")),
    _p("solid.pressure_tolerance", 1.0e-4, "1",
       "solid.pressure = implicit: the conjugate gradients stop when the residual's 2-norm is this fraction of the "
       "right-hand side's", low=0.0, low_inclusive=False, high=0.1, rebuild=False),
    _p("solid.pressure_max_iterations", 200, "1", "solid.pressure = implicit: the cap on its iterations per step",
       kind="int", low=1, high=100000, rebuild=False),
    _p("solid.artificial_viscosity_alpha", 0.1, "1", "Monaghan artificial viscosity alpha (linear term)", low=0.0,
       high=10.0, rebuild=False),
    _p("solid.artificial_viscosity_beta", 0.0, "1", "Monaghan artificial viscosity beta (quadratic term)",
       low=0.0, high=10.0, rebuild=False),
    _p("solid.artificial_stress_epsilon", _by_scheme("solid.artificial_stress_epsilon"), "1",
       "Gray's artificial stress epsilon (0: off). The paper's 'sph' gradient needs it against the tensile "
       "instability (0.15; Gray: 0.3); the quadratic fit needs none, and with it a nearly incompressible body grows "
       "a spurious mode (docs/method.md)" + _SET_BY_SCHEME, low=0.0, high=1.0, rebuild=False),
    _p("solid.artificial_stress_exponent", 4, "1", "Gray's artificial stress exponent n in f_ab^n", kind="int",
       low=1, high=MAX_ART_EXPONENT, rebuild=False),
]

# The incompressible fluid by iterative density correction (Okaji 2002; Satake et al. sec. 2.2).
FLUID = [
    _p("fluid.density", 1000.0, "kg/m^3", "Rest density rho0 of the water (walls stand for the same density)",
       low=1.0, high=1.0e5),
    _p("fluid.kernel", "cubic_spline", "",
       "The water's smoothing kernel, support 2h: 'cubic_spline' (M4, the paper's eq. (1)) or 'wendland_c2' "
       "(Wendland's C2, which keeps a flow ordered at h / dp 1.75-2 where the spline's pairs clump; "
       "numerics/kernels.py, docs/validation/OPEN.md 7). The solid keeps the cubic spline", kind="str",
       choices=tuple(KERNELS)),
    _p("fluid.viscosity", 1.0e-6, "m^2/s", "Kinematic viscosity nu of the laminar term, eq. (9) (Morris form)",
       low=0.0, high=1.0, rebuild=False),
    _p("fluid.density_tolerance", 0.01, "1",
       "The correction stops once the compression (rho - rho0)_+ / rho0 is at most this (the paper: 1 %)",
       low=0.0, low_inclusive=False, high=0.5, rebuild=False),
    _p("fluid.tolerance_on", "max", "", "Which compression measure the tolerance governs (both are reported)",
       kind="str", choices=("max", "mean"), rebuild=False),
    _p("fluid.partial_iteration", False, "",
       "The correction's last iteration taken only in the part that brings the compression to the tolerance, so a "
       "step's work, and the pressure the water reads, changes continuously rather than by whole iterations (false: "
       "the paper's; docs/method.md)", kind="bool", rebuild=False),
    _p("fluid.shifting", 0.0, "1",
       "A of the shift that moves the water after each step down its particles' concentration gradient, "
       "dr = -A h U dt grad C, none in the free surface's band (0: none, the paper's; fluid/shifting.py, "
       "docs/method.md)", low=0.0, high=2.0),
    _p("fluid.shifting_speed", "largest", "", "U of the shift: the water's largest speed (Xu et al. 2009) or each "
       "particle's own (Lind et al. 2012)", kind="str", choices=("largest", "own")),
    _p("fluid.correction_coefficient", 0.0, "m/s",
       "c of eq. (7), how far one correction moves a particle (0: automatic, c = correction_kappa * h / dt)",
       low=0.0, high=1.0e4, rebuild=False),
    _p("fluid.correction_kappa", 1.0, "1",
       "With the automatic c: kappa = c dt / h, the size of one correction iteration (a compressed block relaxes monotonically up to about 1.6)",
       low=0.0, low_inclusive=False, high=2.0, rebuild=False),
    _p("fluid.min_iterations", 0, "1", "Correction iterations done every step even when already converged",
       kind="int", low=0, high=1000, rebuild=False),
    _p("fluid.max_iterations", 200, "1",
       "Correction iterations at most per step; a step that reaches it is counted and reported", kind="int",
       low=1, high=100000, rebuild=False),
    _p("fluid.cfl", 0.2, "1", "Fluid time step dt = cfl * h / |v|max (also cfl * sqrt(h / |g|), 0.125 h^2 / nu)",
       low=0.0, low_inclusive=False, high=1.0, rebuild=False),
    _p("fluid.time_step", 0.0, "s",
       "Forced fluid time step (0: automatic); refused above the stable limit, clamped to it with a warning if "
       "the limit falls below it during the run", low=0.0, high=1.0, rebuild=False),
    _p("fluid.min_time_step", 1.0e-7, "s", "A stable fluid step below this stops the run as diverged",
       low=0.0, low_inclusive=False, high=1.0, rebuild=False),
    _p("fluid.settle_time", 0.0, "s",
       "Before t = 0 the water settles at rest for this long (the solid held as built, the scene's release plates "
       "holding the water: a dam break's gate, the gap under a gate), all released at t = 0; 0: the water starts "
       "on its lattice with no pressure (the paper)", low=0.0, high=10.0),
    _p("fluid.max_density_error", 0.2, "1",
       "A step ending with max compression above this stops the run as diverged (watchdog)", low=0.0,
       low_inclusive=False, high=10.0, rebuild=False),
]

# Fluid-structure coupling (Satake et al. sec. 2.3; coupling/). Only scenes with both a solid and a fluid.
COUPLING = [
    _p("coupling.model", "pressure", "",
       "Fluid's push on the solid: 'pressure' equal and opposite pressure pair forces (momentum-conserving; the "
       "one that reproduces the paper's gate); 'seed' the paper's eqs. (10)-(11) (correction displacement, "
       "projected on surface normals, times gamma), which carry almost no load",
       kind="str", choices=("seed", "pressure"), rebuild=False),
    _p("coupling.gamma", 10.0, "1", "Factor gamma of eq. (11), 'seed' model (the paper: 10)", low=0.0, high=1.0e4,
       rebuild=False),
    _p("coupling.substeps", 0, "1",
       "Solid sub-steps per fluid step (0: ceil(fluid dt / stable solid dt); a forced value below that is "
       "replaced by it with a warning); the paper: 200", kind="int", low=0, high=100000, rebuild=False),
    _p("coupling.relaxation", 1.0, "1",
       "The push held over the solid's sub-steps is this times the one from the fluid step just taken plus the rest "
       "times the previous push (1: the paper's staggered push). Below 2 / (1 + m_added / m_solid) it damps the "
       "step-to-step alternation of a light solid under deep water (the added-mass instability of a staggered "
       "coupling); a static answer does not depend on it; it lags the load by about dt (1 - relaxation) / relaxation",
       low=0.0, low_inclusive=False, high=1.0, rebuild=False),
    _p("coupling.push_ramp", False, "",
       "The push goes linearly over the solid's sub-steps from the previous fluid step's to this one's (in at most 16 "
       "pieces) instead of held (false: the paper's): a held push changes in a staircase at the fluid step's "
       "frequency, which rings a stiff solid whose mode lies near it; the push's mean over a step lags by dt / 2",
       kind="bool", rebuild=False),
    _p("coupling.surface_threshold", 0.4, "1",
       "A solid particle is a surface particle when |sum_b V_b grad W_ab| h exceeds this (0.59 at a flat "
       "face, 0.06 one layer in, 0 deeper)", low=0.0, low_inclusive=False, high=2.0),
]

def check_combinations(values):
    """SceneError for settings that are each in range but do not fit together (the solid's scheme keys, the fluid's
    iteration bounds); only the keys a scene has are checked."""
    v = values
    if "solid.pressure" in v:
        if v["solid.pressure"] == "implicit" and v["solid.velocity_gradient"] != "quadratic":
            raise SceneError(f"solid.pressure = implicit solves with the quadratic fit's pair weights; "
                             f"solid.velocity_gradient = {v['solid.velocity_gradient']}: allowed: quadratic (or "
                             f"solid.pressure = explicit)")
        if v["solid.nodal_integration"] == "gradient" and v["solid.velocity_gradient"] != "quadratic":
            raise SceneError(f"solid.nodal_integration = gradient needs the quadratic fit's second derivatives; "
                             f"solid.velocity_gradient = {v['solid.velocity_gradient']}: allowed: quadratic (or "
                             f"solid.nodal_integration = plain)")
        if v["solid.volumetric_gradient"] and v["solid.nodal_integration"] != "gradient":
            raise SceneError("solid.volumetric_gradient = true is the volumetric part of the strain-gradient "
                             f"integration; solid.nodal_integration = {v['solid.nodal_integration']}: allowed: "
                             "gradient (or solid.volumetric_gradient = false)")
    if "solid.smoothing_ratio" in v:
        check_own_smoothing_ratio("solid.smoothing_ratio", v["solid.smoothing_ratio"])
    if "fluid.min_iterations" in v and v["fluid.min_iterations"] > v["fluid.max_iterations"]:
        raise SceneError(f"fluid.min_iterations = {v['fluid.min_iterations']}: above fluid.max_iterations = "
                         f"{v['fluid.max_iterations']}; allowed: at most fluid.max_iterations")


def check_own_smoothing_ratio(key, value):
    """SceneError for an own h / dp (the solid's, a probe's) between 0, which means numerics.smoothing_ratio, and 1."""
    if 0.0 < value < 1.0:
        raise SceneError(f"{key} = {value:g}: out of range; allowed: in [1, 2], or 0 (numerics.smoothing_ratio)")


def solid_smoothing_ratio(values):
    """The solid's h / dp: solid.smoothing_ratio, or numerics.smoothing_ratio where that is 0 or the scene has no
    solid."""
    return values.get("solid.smoothing_ratio") or values["numerics.smoothing_ratio"]


def widest_smoothing_ratio(values):
    """The larger of the water's and the solid's h / dp: the one a periodic slab's neighbour lists must fit."""
    return max(values["numerics.smoothing_ratio"], solid_smoothing_ratio(values))


SECTIONS_BY_PHASE = {"common": COMMON, "solid": SOLID, "fluid": FLUID, "coupling": COUPLING}
# Phases a scene may have; a scene whose builder lacks one refuses its section by name.
PHASE_NAMES = ("solid", "fluid", "walls", "coupling")


@dataclass
class Schema:
    """The keys a given builder's scenes may set: common + its phases' sections + its geometry."""
    params: dict = field(default_factory=dict)

    @classmethod
    def for_builder(cls, phases, geometry_params):
        params = {}
        for p in COMMON:
            params[p.key] = p
        for phase in phases:
            for p in SECTIONS_BY_PHASE.get(phase, []):
                params[p.key] = p
        for p in geometry_params:
            params[p.key] = p
        return cls(params)

    def sections(self):
        return sorted({p.section for p in self.params.values()})

    def check_key(self, key, all_sections, absent=None):
        """SceneError unless `key` is declared here; names the phase when the key exists for other scenes, and why
        this scene lacks it where `absent` ({section: what would give it}) says."""
        if key in self.params:
            return self.params[key]
        section = key.split(".", 1)[0]
        if section in all_sections and section not in self.sections():
            why = f"; allowed: its sections' keys (it would have '{section}' with {absent[section]})" \
                if absent and section in absent else ""
            raise SceneError(f"{key}: this scene has no '{section}' section (its sections: "
                             f"{', '.join(self.sections())}){why}")
        name = key.split(".", 1)[1] if "." in key else key
        if section not in self.sections():
            near = difflib.get_close_matches(section, self.sections(), n=1, cutoff=0.6)
            guess = f"{near[0]}.{name}" if near else None
            hint = (f"; did you mean {guess}?" if guess in self.params else "")
            raise SceneError(f"{key}: unknown section '{section}' (this scene's sections: "
                             f"{', '.join(self.sections())}){hint}")
        close = difflib.get_close_matches(key, [k for k in self.params if k.startswith(section + ".")], n=1,
                                          cutoff=0.6)
        hint = f"; did you mean {close[0]}?" if close else ""
        raise SceneError(f"{key}: unknown key{hint}")
