"""python.soak: scrub the Soft Body filter back and forth over many random frame times while
changing properties in between, and check every frame against a fresh run.

On data/jelly.vtu, Device CPU (and then GPU (EGL) where that device really runs: field data
Device says so; otherwise the GPU part is reported as skipped with the reason), a seeded RNG
draws --frames request times: mostly frame times of the grid (random jumps and short scrubs of
a few frames either way), some off the grid. Between requests it changes

* properties that change the motion (YoungsModulus, Gravity, Integrator, Method Mass-Spring <->
  XPBD, and under XPBD the link compliance): the next frame must be the new motion's;
* properties the current method ignores (PBD/XPBD settings under Mass-Spring, Mass-Spring
  settings under XPBD, EndTime, CacheMemoryLimit): the cache must stay: the last frame asked
  for is served again without a single simulation step and with the same number of cached
  frames (SimulatedStepsTotal and CachedFrames of the filter);
* an out-of-range value of a property the method reads (YoungsModulus -1, Iterations 0 under
  XPBD): an error and an empty output; put back, the cache is still there (no step).

Checks, after every request:

* the frame equals, bit for bit, the frame a fresh filter with the same properties computes
  when updated straight to that time (points and Velocity). Bitwise, not to a tolerance: the
  simulation is deterministic (same thread count, race-free parallel loops, snapshot restore
  copies the complete dynamic state), and resuming from a cached frame runs exactly the
  advance() calls a straight run makes, so any difference at all is a bug (a stale cache, a
  missing field in the snapshot), not rounding;
* the frame cache obeys CacheMemoryLimit (1 or 2 MiB here, about 38 or 77 jelly frames, far
  fewer than the frames visited, so eviction happens all along): the bytes the cache counts
  are within the limit, and so is the number of cached frames times the frame's payload
  (positions and velocities) computed here independently, unless frame 0 is the only frame
  (it is kept whatever the budget); frame 0 is served without stepping whenever asked for;
* memory: the process's resident set (VmRSS of /proc/self/status) at the end of the run (the
  mean over its last 10 requests) is not more than --rss-bound-mib (4 MiB) above where it was
  after a warm-up; the peak is printed beside it. A leak accumulates to the end, while the
  allocators' transient peaks (llvmpipe's among them) come and go. Each fresh filter builds
  and frees a whole simulation and each request allocates outputs; leaking one jelly frame per
  request would add ~4 MiB. scripts/lsan_soak.sh runs this script under LeakSanitizer.

Runtime (2 shared cores): ~20 s for the CPU part, ~60 s for the GPU part on llvmpipe, nearly all
of it in the fresh reference runs; --gpu-frames trims the GPU part.

Both filters' internals come from the client-side object: PrintSelf (str()) carries
SimulatedStepsTotal and "CachedFrames: N (B bytes)"; GetSimulatedStepsTotal() and
GetNumberOfCachedFrames() are used too when the plugin's module is Python-wrapped (it is not in
this build: the client-side object is a vtkUnstructuredGridAlgorithm to Python). The fresh
filters are unregistered servermanager proxies, released after each use.
"""

import collections
import ctypes
import hashlib
import math
import os
import random
import re
import sys
import time

import numpy as np
from paraview import servermanager
from paraview.simple import *  # noqa: F401,F403
from vtkmodules.util import numpy_support

import softbody_testing as sbt


def extra_arguments(parser):
    parser.add_argument("--frames", type=int, default=200, help="requests per device")
    parser.add_argument("--gpu-frames", type=int, default=None,
                        help="requests for the GPU part (default: --frames)")
    parser.add_argument("--seed", type=int, default=11052024)
    parser.add_argument("--rss-bound-mib", type=float, default=4.0,
                        help="allowed VmRSS growth after the warm-up [MiB]")
    parser.add_argument("--warmup", type=int, default=40, help="requests before the RSS baseline")
    parser.add_argument("--devices", default="CPU,GPU (EGL)")


args = sbt.parse_args(__doc__, extra_arguments)
LoadPlugin(args.plugin, remote=False, ns=globals())
started = time.monotonic()

# The floor is raised to 0.1 m under the jelly (bottom at 0.3 m): it lands at t = 0.14 s and
# wobbles on the floor for the rest of the interval, so the frames depend on the material and
# the integrator, not only on free fall, while a fresh run to any time stays short.
FLOOR_ORIGIN = [0.0, 0.0, 0.2]
END_TIME = 0.25
FRAME_INTERVAL = 0.0025         # 101 frames on the grid, 2.6 MiB of jelly frames
END_TIMES = [END_TIME, 0.2, 0.2013]  # EndTime is toggled (it keeps the cache); 0.2013 is off the grid
MIB = 1 << 20

reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data_dir, "jelly.vtu")])
reader.UpdatePipeline()
rest = reader.GetClientSideObject().GetOutputDataObject(0)
NPOINTS = rest.GetNumberOfPoints()
FRAME_PAYLOAD = 2 * NPOINTS * 3 * 8  # positions + velocities, doubles

# The properties a fresh filter copies (every one the proxy has, except the inputs and the
# information-only ones such as TimestepValues).
SKIP_PROPERTIES = {"Input", "Surface"}


def last_frame(end_time):
    """The last grid frame at or before end_time (vtkSoftBodyFrameGrid::LastFrame)."""
    n = end_time / FRAME_INTERVAL
    nearest = round(n)
    return nearest if abs(nearest - n) <= 1e-9 * max(n, 1.0) else math.floor(n)


def release_free_heap():
    """glibc keeps freed memory in its arenas for reuse (more arenas the more threads allocate
    at once, as under a parallel ctest), so VmRSS would count memory that is free; malloc_trim
    hands it back first, so the check sees what is still allocated, which is what leaks."""
    try:
        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass  # not glibc: VmRSS as it is


def rss_kib():
    release_free_heap()
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS in /proc/self/status")


def plain(value):
    """A property's value as plain Python data (getattr returns live vector properties)."""
    if isinstance(value, (str, int, float)) or value is None:
        return value
    return tuple(value)


def properties_of(proxy):
    return tuple((name, plain(getattr(proxy, name)))
                 for name in proxy.ListProperties()
                 if name not in SKIP_PROPERTIES
                 and not proxy.GetProperty(name).SMProperty.GetInformationOnly())


def internals(proxy):
    """(SimulatedStepsTotal, cached frames, cached bytes) of the filter behind a proxy."""
    obj = proxy.GetClientSideObject()
    text = str(obj)  # PrintSelf
    steps = re.search(r"SimulatedStepsTotal: (\d+)", text)
    cached = re.search(r"CachedFrames: (\d+) \((\d+) bytes\)", text)
    if not steps or not cached:
        raise AssertionError("PrintSelf lacks SimulatedStepsTotal / CachedFrames:\n" + text)
    result = (int(steps.group(1)), int(cached.group(1)), int(cached.group(2)))
    if hasattr(obj, "GetSimulatedStepsTotal"):
        assert obj.GetSimulatedStepsTotal() == result[0], "GetSimulatedStepsTotal vs PrintSelf"
        assert obj.GetNumberOfCachedFrames() == result[1], "GetNumberOfCachedFrames vs PrintSelf"
    return result


def frame_of(proxy):
    """Points and Velocity of the Mesh output as arrays (copies), and the output's field data."""
    mesh = proxy.GetClientSideObject().GetOutputDataObject(sbt.MESH_PORT)
    if mesh is None or mesh.GetNumberOfPoints() != NPOINTS:
        raise AssertionError(f"no mesh output ({mesh})")
    points = numpy_support.vtk_to_numpy(mesh.GetPoints().GetData()).copy()
    velocity = numpy_support.vtk_to_numpy(mesh.GetPointData().GetArray("Velocity")).copy()
    return points, velocity, mesh


def digest(points, velocity):
    return hashlib.sha256(np.ascontiguousarray(points, dtype=np.float64).tobytes() +
                          np.ascontiguousarray(velocity, dtype=np.float64).tobytes()).hexdigest()


class Reference:
    """Frames of fresh filters: for each (properties, time) a new, unregistered SoftBody proxy
    with the same properties, updated straight to the time, then released. Only a digest of
    each frame is kept (the soak revisits times, so a frame is computed once per settings), so
    the reference itself does not grow the process by whole frames."""

    def __init__(self):
        self.digests = {}
        self.runs = 0
        self.seconds = 0.0

    def fresh_frame(self, properties, t):
        start = time.monotonic()
        fresh = servermanager.filters.SoftBody(Input=reader)
        for name, value in properties:
            setattr(fresh, name, list(value) if isinstance(value, tuple) else value)
        fresh.UpdatePipeline(t)
        steps, _, _ = internals(fresh)
        points, velocity, mesh = frame_of(fresh)
        device = sbt.field_value(mesh, "Device")
        del mesh
        del fresh
        self.runs += 1
        self.seconds += time.monotonic() - start
        return points, velocity, steps, device

    def check(self, properties, t, points, velocity, label):
        # A digest of the key too: ~70 properties per key would make the dict itself grow
        # the process by a few MiB, which would blur the VmRSS check.
        key = hashlib.sha256(repr((properties, t)).encode()).digest()
        expected = self.digests.get(key)
        if expected is None:
            ref_points, ref_velocity, _, _ = self.fresh_frame(properties, t)
            expected = digest(ref_points, ref_velocity)
            self.digests[key] = expected
        if digest(points, velocity) == expected:
            return
        ref_points, ref_velocity, _, _ = self.fresh_frame(properties, t)
        dx = float(np.abs(points - ref_points).max())
        dv = float(np.abs(velocity - ref_velocity).max())
        raise AssertionError(f"{label}: frame at t = {t!r} differs from a fresh run "
                             f"(max |dx| {dx:.3e} m, max |dv| {dv:.3e} m/s)")


MASS_SPRING_INTEGRATORS = ["Euler-Cromer", "Verlet", "Midpoint", "Euler"]
PBD_INTEGRATORS = ["Euler-Cromer", "Verlet"]

# Motion changes: each a function (rng, body) -> description. Values are kept few so that the
# soak revisits settings (and times), which is what a user scrubbing and tweaking does.
def change_youngs(rng, body, device):
    body.YoungsModulus = rng.choice([5e4, 1e5, 2e5])
    return f"YoungsModulus={body.YoungsModulus:g}"


def change_gravity(rng, body, device):
    body.Gravity = rng.choice([[0.0, 0.0, -9.81], [0.0, 0.0, -5.0], [1.5, 0.0, -9.81]])
    return f"Gravity={list(body.Gravity)}"


def change_integrator(rng, body, device):
    choices = MASS_SPRING_INTEGRATORS if body.Method == "Mass-Spring" else PBD_INTEGRATORS
    body.Integrator = rng.choice([c for c in choices if c != body.Integrator])
    return f"Integrator={body.Integrator}"


def change_method(rng, body, device):
    if body.Method == "Mass-Spring":
        body.Method = "XPBD"
        if body.Integrator not in PBD_INTEGRATORS:
            body.Integrator = rng.choice(PBD_INTEGRATORS)
    else:
        body.Method = "Mass-Spring"
        body.Device = device  # XPBD ignores Device: the soak may have toggled it
    return f"Method={body.Method} (Integrator={body.Integrator})"


def change_compliance(rng, body, device):
    if body.Method == "Mass-Spring":
        return None  # ignored under Mass-Spring: not a motion change there
    body.XPBDLinkCompliance = rng.choice([1e-4, 1e-3])
    return f"XPBDLinkCompliance={body.XPBDLinkCompliance:g}"


MOTION_CHANGES = [change_youngs, change_gravity, change_integrator, change_method, change_compliance]

# Ignored properties: (name, values) per method; EndTime and CacheMemoryLimit under both.
# (Friction and Restitution are read by every method, so they are in no list.)
IGNORED = {
    "Mass-Spring": [("Iterations", [5, 10, 20]), ("Substeps", [1, 2]),
                    ("Solver", ["Gauss-Seidel", "Jacobi", "Parallel Gauss-Seidel"]),
                    ("XPBDLinkCompliance", [1e-4, 1e-3]), ("PBDLinkStiffness", [1.0, 0.5]),
                    ("VelocityDamping", [0.0, 1.0])],
    "XPBD": [("DampingTime", [2e-3, 5e-3]), ("StrainLimit", [0.0, 1.2]),
             ("YoungsModulus", [5e4, 1e5, 2e5]), ("PBDLinkStiffness", [1.0, 0.5]),
             ("MaxInverseMass", [0.0, 1e4]), ("Device", ["CPU", "GPU (EGL)"])],
    "both": [("EndTime", END_TIMES), ("CacheMemoryLimit", [1, 2])],
}


def soak(device, frames, rng, reference):
    label = f"[{device}]"
    body = SoftBody(Input=reader, Method="Mass-Spring", Device=device, EndTime=END_TIME, FrameInterval=FRAME_INTERVAL,
                    FloorOrigin=FLOOR_ORIGIN, CacheMemoryLimit=1)
    body.UpdatePipeline(0.0)
    _, _, mesh = frame_of(body)
    used = sbt.field_value(mesh, "Device")
    if used != device:
        warnings = sbt.field_value(mesh, "Warnings") or ""
        Delete(body)
        return f"Device is {used!r}, not {device!r}: {warnings.strip()}"

    grid_last = round(END_TIME / FRAME_INTERVAL)
    t = 0.0
    k = 0
    properties = properties_of(body)
    counts = {"requests": 0, "off_grid": 0, "motion_changes": 0, "ignored_changes": 0,
              "ignored_checks": 0, "frame0_checks": 0, "max_cached": 0, "min_cached": 10**9,
              "evicting_requests": 0, "on_device": 0,
              "refused_values": 0}
    rss_baseline = None
    rss_max = 0
    rss_samples = []
    rss_last = collections.deque(maxlen=10)  # the run's end state, for the leak check
    soak_seconds = 0.0

    for request in range(frames):
        # 1. Maybe change properties the method ignores; the cache must survive them. The last
        #    grid frame asked for (the most recently used) is asked for again: no step at all.
        if request > 0 and rng.random() < 0.15:
            pool = IGNORED["XPBD" if body.Method == "XPBD" else "Mass-Spring"] + IGNORED["both"]
            if k * FRAME_INTERVAL > min(END_TIMES):
                # Keep the last frame on the grid, so it can be asked for again.
                pool = [entry for entry in pool if entry[0] != "EndTime"]
            name, values = rng.choice(pool)
            current = plain(getattr(body, name))
            setattr(body, name, rng.choice([v for v in values if v != current]))
            counts["ignored_changes"] += 1
            before_steps, before_frames, _ = internals(body)
            t_check = k * FRAME_INTERVAL
            start = time.monotonic()
            body.UpdatePipeline(t_check)
            soak_seconds += time.monotonic() - start
            after_steps, after_frames, _ = internals(body)
            what = f"{name}={getattr(body, name)} under {body.Method}"
            if after_steps != before_steps or after_frames > before_frames:
                sbt.check(False, f"{label} {what}: the cache is kept (frame {k} cost "
                                 f"{after_steps - before_steps} steps, cached frames "
                                 f"{before_frames} -> {after_frames})")
            properties = properties_of(body)
            points, velocity, _ = frame_of(body)
            reference.check(properties, t_check, points, velocity, f"{label} after {what}")
            counts["ignored_checks"] += 1

        # 1b. Maybe a value out of range for a property the method reads: an error and an empty
        #     output; the value put back, the cache is still there (the last frame costs no step).
        if request > 0 and rng.random() < 0.04:
            name, bad = ("YoungsModulus", -1.0) if body.Method == "Mass-Spring" else ("Iterations", 0)
            saved = plain(getattr(body, name))
            t_check = k * FRAME_INTERVAL
            errors.clear()
            setattr(body, name, bad)
            body.UpdatePipeline(t_check)
            mesh = body.GetClientSideObject().GetOutputDataObject(sbt.MESH_PORT)
            if not errors.errors or (mesh is not None and mesh.GetNumberOfPoints() > 0):
                sbt.check(False, f"{label} {name}={bad}: an error and an empty output")
            del mesh
            setattr(body, name, saved)
            errors_before = len(errors.errors)
            before_steps, before_frames, _ = internals(body)
            body.UpdatePipeline(t_check)
            after_steps, after_frames, _ = internals(body)
            if errors.errors[errors_before:] or after_steps != before_steps or after_frames != before_frames:
                sbt.check(False, f"{label} {name} back from {bad}: the cache is kept (frame {k} "
                                 f"cost {after_steps - before_steps} steps, cached frames "
                                 f"{before_frames} -> {after_frames}, errors {errors.errors[errors_before:]})")
            counts["refused_values"] += 1

        # 2. Maybe change the motion.
        if request > 0 and rng.random() < 0.08:
            change = rng.choice(MOTION_CHANGES)
            what = change(rng, body, device)
            if what:
                counts["motion_changes"] += 1
                print(f"  {label} request {request}: {what}", flush=True)

        # 3. The next time: a jump or a short scrub on the grid; sometimes a time off the grid,
        #    EndTime itself, frame 0, or a grid time as a script summing FrameInterval gets it
        #    (off by rounding, within the grid's tolerance: served as that grid frame).
        last = last_frame(body.EndTime)
        draw = rng.random()
        if draw < 0.42:
            k = rng.randint(0, last)
            t = k * FRAME_INTERVAL  # exactly what the filter advertises for frame k
        elif draw < 0.80:
            k = min(max(k + rng.choice([-3, -2, -1, 1, 1, 2, 3]), 0), last)
            t = k * FRAME_INTERVAL
        elif draw < 0.85:
            k = rng.randint(1, last)
            t = sum([FRAME_INTERVAL] * k)
        elif draw < 0.88:
            t, k = 0.0, 0
        elif draw < 0.90:
            t = body.EndTime
            k = last
        else:
            t = rng.uniform(0.0, body.EndTime)
            k = math.floor(t / FRAME_INTERVAL)  # as the filter's FrameOf
            counts["off_grid"] += 1

        before_steps, _, _ = internals(body)
        properties_before = properties
        properties = properties_of(body)
        start = time.monotonic()
        body.UpdatePipeline(t)
        soak_seconds += time.monotonic() - start
        steps, cached, cached_bytes = internals(body)
        counts["requests"] += 1
        points, velocity, mesh = frame_of(body)
        if body.Method == "Mass-Spring":
            used = sbt.field_value(mesh, "Device")
            if used != device:
                sbt.check(False, f"{label} request {request}: ran on {used!r}")
            counts["on_device"] += 1  # XPBD runs on the CPU whatever Device says
        del mesh

        # Same frame as a fresh filter with these properties, straight to t.
        reference.check(properties, t, points, velocity, f"{label} request {request}")

        # Frame 0 is never evicted: with unchanged settings, asking for it costs nothing.
        if t == 0.0 and properties == properties_before:
            counts["frame0_checks"] += 1
            if steps != before_steps:
                sbt.check(False, f"{label} request {request}: frame 0 cost {steps - before_steps} steps")

        # The budget: the bytes the cache counts, and frames x payload counted here.
        limit = body.CacheMemoryLimit * MIB
        if cached > 1 and (cached_bytes > limit or cached * FRAME_PAYLOAD > limit):
            sbt.check(False, f"{label} request {request}: {cached} cached frames, {cached_bytes} "
                             f"bytes, payload {cached * FRAME_PAYLOAD} bytes > limit {limit}")
        if cached_bytes < cached * FRAME_PAYLOAD:
            sbt.check(False, f"{label} request {request}: the cache counts {cached_bytes} bytes "
                             f"for {cached} frames of {FRAME_PAYLOAD} bytes of payload")
        counts["max_cached"] = max(counts["max_cached"], cached)
        counts["min_cached"] = min(counts["min_cached"], cached)
        if (cached + 1) * FRAME_PAYLOAD > limit:
            counts["evicting_requests"] += 1

        rss = rss_kib()
        if request + 1 == min(args.warmup, frames // 2):
            rss_baseline = rss
        elif rss_baseline is not None:
            rss_max = max(rss_max, rss)
            rss_last.append(rss)
        if request % 20 == 0 or request + 1 == frames:
            rss_samples.append((request, rss))
            print(f"  {label} request {request}: t={t:.6g} {body.Method}/{body.Integrator} "
                  f"cached {cached} frames ({cached_bytes / MIB:.2f} MiB of {body.CacheMemoryLimit}) "
                  f"steps total {steps} VmRSS {rss / 1024:.1f} MiB", flush=True)

    sbt.check(True, f"{label} {counts['requests']} requests ({counts['off_grid']} off the grid) "
                    f"equal fresh runs bitwise ({reference.runs} fresh runs so far)")
    # That the soak did what it is for (a shortened run, e.g. under a sanitizer, may not).
    enough = frames >= 100
    sbt.check(counts["ignored_checks"] > 0 or not enough,
              f"{label} {counts['ignored_changes']} ignored-property changes kept the cache")
    sbt.check(counts["refused_values"] > 0 or not enough,
              f"{label} {counts['refused_values']} refused values, put back, kept the cache")
    sbt.check(counts["motion_changes"] >= 5 or not enough,
              f"{label} {counts['motion_changes']} motion changes")
    sbt.check(counts["on_device"] >= frames // 4 or not enough,
              f"{label} {counts['on_device']} requests under Mass-Spring on {device} "
              f"(the rest under XPBD)")
    sbt.check(counts["max_cached"] * FRAME_PAYLOAD <= 2 * MIB and (counts["evicting_requests"] > 0 or not enough),
              f"{label} the cache stayed within its budget while evicting (at most "
              f"{counts['max_cached']} frames cached; {counts['evicting_requests']} requests at the limit)")
    rss_end = sum(rss_last) / len(rss_last)
    growth = (rss_end - rss_baseline) / 1024.0
    print(f"  {label} VmRSS samples (request, MiB): "
          + ", ".join(f"({r}, {v / 1024:.1f})" for r, v in rss_samples))
    sbt.check(growth <= args.rss_bound_mib,
              f"{label} VmRSS after warm-up {rss_baseline / 1024:.1f} MiB, at the end "
              f"{rss_end / 1024:.1f} MiB (peak {rss_max / 1024:.1f}): growth {growth:.1f} MiB "
              f"<= {args.rss_bound_mib} MiB")
    print(f"  {label} soak filter updates {soak_seconds:.1f} s", flush=True)
    Delete(body)
    return None


reference = Reference()
errors = sbt.ErrorCapture()
skipped = []
for index, device in enumerate(d.strip() for d in args.devices.split(",")):
    frames = args.frames if device == "CPU" or args.gpu_frames is None else args.gpu_frames
    rng = random.Random(args.seed + index)
    device_start = time.monotonic()
    why = soak(device, frames, rng, reference)
    if why:
        print(f"SKIPPED ({device} part): {why}", flush=True)
        skipped.append(device)
    else:
        print(f"  [{device}] {time.monotonic() - device_start:.1f} s", flush=True)

print(f"fresh runs: {reference.runs} in {reference.seconds:.1f} s; total "
      f"{time.monotonic() - started:.1f} s")
errors.close()
print("python.soak passed" + (f" (skipped: {', '.join(skipped)})" if skipped else ""))
