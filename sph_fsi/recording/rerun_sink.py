"""Rerun recording (rerun-sdk 0.41): to an .rrd file and/or live to a viewer over gRPC.

Entities (only what the scene has):
- `world/solid`, `world/fluid`: the moving particles, Points3D coloured by von Mises stress (solid, viridis)
  and pressure (fluid, plasma); radius half the particle spacing.
- `world/walls`: the fixed particles (walls, the solid's clamp), grey, logged once as static.
- Probes (sph_fsi_core.probes), Scalars: a displacement probe (the built-in scenes' `tip`) as
  `probes/<name>/{dx,dy,dz}` [m]; the other kinds one entity per quantity of their readings, a scalar as
  `probes/<name>/<quantity>` (pressure [Pa], height [m]) and a vector as `probes/<name>/<quantity>/{x,y,z}`
  (point: displacement [m] and velocity [m/s]; water_height: surface, the free surface's point [m]; force [N]).
- `energy/{kinetic,strain}` (solid), `energy/fluid_kinetic` [J]: Scalars.
- `legend/<phase>/{min,max}` [Pa]: the colour map's range at each frame, and a static `legend` text document
  that says which colour map and quantity each entity uses.
- `status`: a TextLog line when the run ends (finished, diverged, water_lost, interrupted, failed).
Timeline `sim_time`: simulated time in seconds (a duration timeline). `world` is right-handed, z up.

Colour range (in the scene's units, Pa): fixed ranges would need knowing the run's stresses in advance, and a
range refitted to every frame would make colours incomparable between frames. So the range only ever widens: the
upper end is the largest 99th percentile of the quantity seen so far in the recording, the lower end 0 for von
Mises stress and, for pressure, the smallest 1st percentile seen so far (or 0 if that is positive). Percentiles,
not extremes, so a single particle spike does not wash out the field. The range in effect is logged with each
frame under `legend/` so a viewer's plot shows the legend at any time.
"""
import uuid

import numpy as np

from sph_fsi.points import PHASE_FLUID, PHASE_SOLID, PHASE_WALL

from .frame import Final, Frame, Static

__all__ = ["RerunSink", "grpc_url", "colour_lut", "probe_scalars"]

_PHASES = {PHASE_SOLID: ("solid", "viridis", "von Mises stress"), PHASE_FLUID: ("fluid", "plasma", "pressure")}


def probe_scalars(readings):
    """[(entity path, value)] of the probes' readings (sph_fsi.points.probe_readings; module docstring)."""
    out = []
    for name, (kind, values) in readings.items():
        if kind == "displacement":
            out += [(f"probes/{name}/{axis}", v) for axis, v in zip(("dx", "dy", "dz"), values["displacement"])]
            continue
        for quantity, value in values.items():
            if isinstance(value, tuple):
                out += [(f"probes/{name}/{quantity}/{axis}", v) for axis, v in zip("xyz", value)]
            else:
                out.append((f"probes/{name}/{quantity}", value))
    return out


def grpc_url(addr):
    """'host:port' or a full rerun+http(s):// URL -> the viewer's proxy URL."""
    if "://" in addr:
        return addr
    return f"rerun+http://{addr}/proxy"


def colour_lut(name, n=256):
    """(n, 3) uint8 colours of a matplotlib colour map."""
    import matplotlib
    return (np.asarray(matplotlib.colormaps[name](np.linspace(0.0, 1.0, n)))[:, :3] * 255 + 0.5).astype(np.uint8)


class _Range:
    """A colour range that only widens: [min(0, lowest 1st percentile), highest 99th percentile] so far."""

    def __init__(self, signed):
        self.signed = signed
        self.low, self.high = 0.0, 0.0

    def update(self, values):
        if len(values):
            lo, hi = np.percentile(values, [1.0, 99.0])
            self.high = max(self.high, float(hi))
            if self.signed:
                self.low = min(self.low, float(lo))
        return self.low, self.high


class RerunSink:
    """Writes Static, Frame and Final items (sph_fsi.recording.frame) to a Rerun recording stream."""

    def __init__(self, rrd_path=None, connect=None, application_id="sph_fsi", recording_id=None):
        if not rrd_path and not connect:
            raise ValueError("RerunSink needs an .rrd path or a viewer address")
        import rerun as rr
        self.rr = rr
        self.rec = rr.RecordingStream(application_id, recording_id=recording_id or str(uuid.uuid4()))
        sinks = []
        if rrd_path:
            sinks.append(rr.FileSink(str(rrd_path)))
        if connect:
            sinks.append(rr.GrpcSink(grpc_url(connect)))
        self.rec.set_sinks(*sinks)
        self.path = str(rrd_path) if rrd_path else None
        self._luts = {code: colour_lut(cmap) for code, (_, cmap, _) in _PHASES.items()}
        self._ranges = {PHASE_SOLID: _Range(signed=False), PHASE_FLUID: _Range(signed=True)}
        self._radius = 0.0
        self.frames = 0
        self._closed = False
        self.rec.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)

    def write(self, item):
        rr, rec = self.rr, self.rec
        rec.set_time("sim_time", duration=float(item.time))
        if isinstance(item, Static):
            self._radius = 0.5 * item.spacing
            lines = [f"# {item.scene}", "", "Colours (range in Pa, logged per frame under `legend/<phase>/{min,max}`;",
                     "it only widens: up to the largest 99th percentile seen so far):", ""]
            lines += [f"- `world/{name}`: {what}, colour map {cmap}" for name, cmap, what in _PHASES.values()]
            lines += ["- `world/walls`: fixed particles (walls, clamp), grey; `world/moving_walls`: walls that move"]
            rec.log("legend", rr.TextDocument("\n".join(lines), media_type=rr.MediaType.MARKDOWN), static=True)
            if len(item.walls):
                rec.log("world/walls", rr.Points3D(item.walls.astype(np.float32), radii=self._radius,
                                                   colors=[150, 150, 150]), static=True)
            return
        if isinstance(item, Final):
            level = "INFO" if item.status == "finished" else "WARN"
            rec.log("status", rr.TextLog(f"{item.status} at t = {item.time:.6g} s", level=level))
            return
        assert isinstance(item, Frame)
        for code, pos, _vel, pressure, vm in item.parts:
            if code == PHASE_WALL:
                rec.log("world/moving_walls", rr.Points3D(pos.astype(np.float32), radii=self._radius or None,
                                                          colors=[110, 110, 160]))
                continue
            name = _PHASES[code][0]
            values = vm if code == PHASE_SOLID else pressure
            low, high = self._ranges[code].update(values)
            lut = self._luts[code]
            scale = (len(lut) - 1) / (high - low) if high > low else 0.0
            idx = np.clip(((values - low) * scale).astype(np.int64), 0, len(lut) - 1)
            rec.log(f"world/{name}", rr.Points3D(pos.astype(np.float32), colors=lut[idx],
                                                 radii=self._radius or None))
            rec.log(f"legend/{name}/min", rr.Scalars(low))
            rec.log(f"legend/{name}/max", rr.Scalars(high))
        for path, value in probe_scalars(item.probes):
            rec.log(path, rr.Scalars(value))
        for key, value in item.energies.items():   # kinetic_energy -> energy/kinetic, fluid_kinetic_energy -> ...
            rec.log(f"energy/{key.removesuffix('_energy')}", rr.Scalars(value))
        self.frames += 1

    def close(self):
        if self._closed:
            return
        self._closed = True
        try:
            self.rec.flush(timeout_sec=60.0)
        finally:
            self.rec.disconnect()
