"""Soft Body demo (run with pvpython under xvfb-run; scripts/demo.sh does both).

    xvfb-run -a -s "-screen 0 1280x1024x24" pvpython scripts/demo.py \
        [--plugin build/lib/paraview-5.11/plugins/SoftBody/SoftBody.so] \
        [--data-dir data] [--output-dir output/demo]

--example jelly (default): drops the jelly (data/jelly.vtu) onto the floor z = 0 with the
filter's default settings (mass-spring, 3 s simulated, a frame every 0.04 s) but for
MaterialModel = Stable Neo-Hookean, the finite-element material whose E and nu the panel shows
(the default spring network only approximates it, and flattens 8 of the jelly's bottom tets
inside out when it lands a second time), and writes
  <output-dir>/softbody.pvd   the run as data: one .vtu per frame under <output-dir>/softbody/
                              (the deformed mesh with Velocity, Displacement, VolumeRatio) and,
                              as further parts of every frame, the floor (the filter's Floor
                              output) and the obstacles
  <output-dir>/softbody.png   a rendered late frame: the body resting on the floor
  <output-dir>/softbody.gif   the animation, every frame rendered (python3-pil assembles it)
  <output-dir>/softbody.pvsm  a ParaView state of the scene: with the plugin loaded,
                              `paraview --state=<output-dir>/softbody.pvsm` opens it ready to Play
--example torus: voxelizes data/torus.vtp into a particle lattice (Soft Body Voxelize), drops it
with XPBD and renders the torus surface skinned onto the particles (the Surface output), not the
particles; writes the same four files as torus.* (the pvd's frames: the moving surface, .vtp).
--example pile: three jellies (one input of three connected bodies) dropped from staggered
heights onto a block obstacle standing on the floor and onto each other (mass-spring,
Projective Dynamics, Stable Neo-Hookean, Collisions = Obstacles + Bodies); writes the same four
files as pile.*.
Exits with status 1 if an output is missing, the body did not end on the floor (jelly, torus),
a pile body ended inside the block or below the floor, or tets turned inside out in some frame
(jelly: any; pile: more than 1 %).
"""

import argparse
import os
import sys
import time

_ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
_DEFAULT_PLUGIN = os.path.join(_ROOT, "build", "lib", "paraview-5.11", "plugins", "SoftBody",
                               "SoftBody.so")


def parse_args():
    parser = argparse.ArgumentParser(description="Soft Body demo: a jelly falling onto a floor.")
    parser.add_argument("--plugin", default=os.environ.get("SOFTBODY_PLUGIN_FILE", _DEFAULT_PLUGIN),
                        help="the built SoftBody.so (default: %(default)s)")
    parser.add_argument("--data-dir", default=os.path.join(_ROOT, "data"),
                        help="folder holding jelly.vtu (default: %(default)s)")
    parser.add_argument("--output-dir", default=os.path.join(_ROOT, "output", "demo"),
                        help="where to write softbody.pvd and softbody.png (default: %(default)s)")
    parser.add_argument("--screenshot-time", type=float, default=None,
                        help="simulated time of the rendered frame, s (default: the last frame)")
    parser.add_argument("--example", choices=["jelly", "torus", "pile"], default="jelly",
                        help="which body to drop (default: %(default)s)")
    parser.add_argument("--size", type=int, nargs=2, default=[1280, 800], metavar=("W", "H"),
                        help="image size in pixels (default: %(default)s)")
    parser.add_argument("--animation-width", type=int, default=640, metavar="W",
                        help="width of the animated GIF in pixels, 0 for none (default: "
                             "%(default)s; the height keeps the image's aspect)")
    return parser.parse_args()


def field_text(dataset, name):
    array = dataset.GetFieldData().GetAbstractArray(name)
    if array is None or array.GetNumberOfValues() == 0:
        return "-"
    if array.IsA("vtkStringArray"):
        return "; ".join(array.GetValue(i) for i in range(array.GetNumberOfValues())) or "none"
    return ", ".join(f"{array.GetTuple(0)[c]:.6g}" for c in range(array.GetNumberOfComponents()))


def floor_plane_corners(origin, normal, center, half_size):
    """Origin, Point1, Point2 of a square on the floor plane around `center`'s projection."""
    import numpy as np
    n = np.asarray(normal, dtype=float)
    n /= np.linalg.norm(n)
    c = np.asarray(center, dtype=float)
    c = c - np.dot(c - np.asarray(origin, dtype=float), n) * n   # project onto the floor
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(n, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    o = c - half_size * (e1 + e2)
    return list(o), list(o + 2.0 * half_size * e1), list(o + 2.0 * half_size * e2)


def add_static_parts(pvd, part_files):
    """Adds each file of `part_files` (relative to the .pvd's folder) to every time step of the
    .pvd as parts 1, 2, ...: ParaView reads the collection as one multiblock per frame, so the
    floor and the obstacles open with the body."""
    import xml.etree.ElementTree as ET
    tree = ET.parse(pvd)
    collection = tree.getroot().find("Collection")
    frames = [d for d in collection.findall("DataSet") if d.get("part", "0") == "0"]
    for frame in frames:
        for k, part_file in enumerate(part_files, start=1):
            collection.append(ET.Element("DataSet", timestep=frame.get("timestep"), part=str(k),
                                         file=part_file))
    ET.indent(tree, space="  ")
    tree.write(pvd, xml_declaration=False)


def save_gif(frame_files, gif, seconds_per_frame):
    """Assembles the rendered PNG frames into a looping animated GIF (python3-pil); False when
    PIL is missing."""
    try:
        from PIL import Image
    except ImportError:
        return False
    images = [Image.open(f).convert("RGB") for f in frame_files]
    # One shared adaptive palette from the middle frame: the scene's colours hardly change.
    palette = images[len(images) // 2].quantize(colors=255, method=Image.Quantize.MEDIANCUT)
    frames = [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
    frames[0].save(gif, save_all=True, append_images=frames[1:], loop=0, optimize=True,
                   duration=max(20, int(round(1000 * seconds_per_frame))))
    return True


# The pile's obstacle: a block (a table) standing on the floor, and where the three jellies
# start: offsets from the jelly's own position (0.3 x 0.3 x 0.2 m, bottom at z = 0.3), metres.
PILE_BLOCK_BOUNDS = (-0.25, 0.25, -0.25, 0.25, 0.0, 0.25)
PILE_OFFSETS = ((0.03, 0.0, 0.0), (-0.03, 0.03, 0.25), (0.0, -0.03, 0.5))


def build_pipeline(pvs, args, input_file):
    """The example's pipeline: (rest-shape source, Soft Body, output port shown, label, the
    obstacles to show with it)."""
    if args.example == "pile":
        reader = pvs.XMLUnstructuredGridReader(registrationName="jelly.vtu", FileName=[input_file])
        moved = [pvs.Transform(registrationName=f"jelly {k + 1}", Input=reader,
                               Transform="Transform") for k in range(len(PILE_OFFSETS))]
        for transform, offset in zip(moved, PILE_OFFSETS):
            transform.Transform.Translate = list(offset)
        # One input, three connected bodies (points not merged).
        bodies = pvs.AppendDatasets(registrationName="three jellies", Input=moved)
        b = PILE_BLOCK_BOUNDS
        block = pvs.Box(registrationName="Obstacle", XLength=b[1] - b[0], YLength=b[3] - b[2],
                        ZLength=b[5] - b[4], Center=[(b[0] + b[1]) / 2, (b[2] + b[3]) / 2,
                                                     (b[4] + b[5]) / 2])
        # Projective Dynamics at 2 ms: its numerical damping calms the jellies' wobble, which at
        # Euler-Cromer's stable step makes them slip off each other and tumble away (contact
        # friction acts per point on that point's own load, which the wobble keeps changing).
        # Even so the upper two slide off the lower one's rounded top; the floor's friction
        # (in the implicit solve, README) stops them within a metre of the block.
        body = pvs.SoftBody(registrationName="SoftBody", Input=bodies, Obstacles=[block],
                            Collisions="Obstacles + Bodies", Integrator="Projective Dynamics",
                            MaterialModel="Stable Neo-Hookean",
                            TimeStep=0.002, StaticFriction=0.6, DynamicFriction=0.5, EndTime=2.0)
        print(f"demo: three jellies ({input_file}) onto a block and onto each other: mass-spring "
              f"({body.Integrator}, {body.MaterialModel}), Collisions = {body.Collisions}, static / dynamic friction "
              f"{body.StaticFriction:g} / {body.DynamicFriction:g}", flush=True)
        return bodies, body, 0, "three jellies dropped onto a block and each other", [block]
    if args.example == "jelly":
        reader = pvs.XMLUnstructuredGridReader(registrationName="jelly.vtu", FileName=[input_file])
        body = pvs.SoftBody(registrationName="SoftBody", Input=reader,
                            MaterialModel="Stable Neo-Hookean")
        print(f"demo: {input_file}: mass-spring ({body.Integrator.GetData()}, "
              f"{body.MaterialModel.GetData()}, E = {body.YoungsModulus:g} Pa, nu = {body.PoissonRatio:g}, "
              f"density {body.Density:g} kg/m^3)", flush=True)
        return reader, body, 0, "jelly dropped on the floor", []
    surface = pvs.XMLPolyDataReader(registrationName="torus.vtp", FileName=[input_file])
    lattice = pvs.SoftBodyVoxelize(registrationName="Voxelize", Input=surface, Resolution=28,
                                  Density=1100.0)
    body = pvs.SoftBody(registrationName="SoftBody", Input=lattice, Surface=surface,
                        Method="XPBD", Iterations=10, Substeps=4, XPBDLinkCompliance=2e-4,
                        Restitution=0.2, EndTime=2.5)
    # Four substeps: at one, ten Gauss-Seidel iterations per 1/60 s do not carry the floor's
    # support up through the lattice as it lands, and the torus ends crushed, its skinned
    # surface crumpled with a sawtooth rim (10 % of its size off a rigid motion of its rest
    # shape, where four substeps leave it within 0.1 %: the check in main()).
    lattice.UpdatePipeline()
    particles = lattice.GetDataInformation().GetNumberOfPoints()
    print(f"demo: {input_file}: voxelized into {particles} particles, XPBD "
          f"(link compliance {body.XPBDLinkCompliance:g} m/N, {body.Iterations} iterations)",
          flush=True)
    return (surface, body, 3, f"voxelized torus ({particles} particles, XPBD), its surface skinned on",
            [])


def main():
    args = parse_args()
    name = {"jelly": "softbody", "torus": "torus", "pile": "pile"}[args.example]
    input_file = os.path.join(args.data_dir, "torus.vtp" if args.example == "torus" else "jelly.vtu")
    for path, what in ((args.plugin, "plugin"), (input_file, "input")):
        if not os.path.isfile(path):
            print(f"demo: {what} not found: {path}", file=sys.stderr)
            return 1
    os.makedirs(args.output_dir, exist_ok=True)
    pvd = os.path.join(args.output_dir, name + ".pvd")
    png = os.path.join(args.output_dir, name + ".png")
    gif = os.path.join(args.output_dir, name + ".gif")
    pvsm = os.path.join(args.output_dir, name + ".pvsm")
    for stale in (pvd, png, gif, pvsm):
        if os.path.exists(stale):
            os.remove(stale)
    # Frames of an earlier run (perhaps with more frames) would be mixed with this run's.
    frames_dir = os.path.join(args.output_dir, name)
    if os.path.isdir(frames_dir):
        for entry in os.listdir(frames_dir):
            if entry.startswith((name + "_", "frame_", "floor", "obstacle_")):
                os.remove(os.path.join(frames_dir, entry))

    import paraview.simple as pvs
    # Loads the plugin into this process (remote=False) and adds SoftBody() to paraview.simple.
    pvs.LoadPlugin(args.plugin, remote=False)

    reader, body, port, what, obstacles = build_pipeline(pvs, args, input_file)
    body.UpdatePipelineInformation()
    times = list(body.TimestepValues)
    print(f"demo: simulating {times[-1]:g} s, {len(times)} frames every {body.FrameInterval:g} s",
          flush=True)

    # All frames into one .pvd (+ <name>/<name>_0_<k>.vt*): the writer steps through the
    # filter's TimestepValues; the filter simulates forward once, frame after frame.
    start = time.perf_counter()
    pvs.SaveData(pvd, proxy=pvs.OutputPort(body, port), WriteTimeSteps=1, CompressorType="ZLib")
    simulated = time.perf_counter() - start
    print(f"demo: simulated and wrote {len(times)} frames in {simulated:.1f} s", flush=True)
    # The floor and the obstacles do not move: written once, referenced by every frame.
    static_parts = []
    if body.Floor:
        floor_file = os.path.join(name, "floor.vtp")
        pvs.SaveData(os.path.join(args.output_dir, floor_file), proxy=pvs.OutputPort(body, 4))
        static_parts.append(floor_file)
    for k, obstacle in enumerate(obstacles):
        obstacle_file = os.path.join(name, f"obstacle_{k}.vtp")
        pvs.SaveData(os.path.join(args.output_dir, obstacle_file), proxy=obstacle)
        static_parts.append(obstacle_file)
    add_static_parts(pvd, static_parts)

    # The frame to render (the cache makes this free).
    t_shot = times[-1] if args.screenshot_time is None else \
        min(times, key=lambda t: abs(t - args.screenshot_time))
    body.UpdatePipeline(t_shot)
    frame = body.GetClientSideObject().GetOutputDataObject(0)
    shown = body.GetClientSideObject().GetOutputDataObject(port)
    rest_bounds = reader.GetDataInformation().GetBounds()
    print(f"demo: frame t = {t_shot:g} s: SimulationTime {field_text(frame, 'SimulationTime')} s, "
          f"{field_text(frame, 'StepCount')} steps of {field_text(frame, 'TimeStep')} s "
          f"(stable {field_text(frame, 'StableTimeStep')} s), total mass "
          f"{field_text(frame, 'TotalMass')} kg")
    print(f"demo: plan: {field_text(frame, 'Plan')}")
    print(f"demo: warnings: {field_text(frame, 'Warnings')}")
    bounds = shown.GetBounds()
    print(f"demo: body z range [{bounds[4]:.4f}, {bounds[5]:.4f}] m "
          f"(at rest before the fall: [{rest_bounds[4]:.4f}, {rest_bounds[5]:.4f}] m)", flush=True)

    # --- render -------------------------------------------------------------------------------
    start = time.perf_counter()
    view = pvs.CreateView("RenderView")
    view.ViewSize = list(args.size)
    view.OrientationAxesVisibility = 0
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.Background = [0.32, 0.34, 0.43]
    if hasattr(view, "Background2"):
        view.BackgroundColorMode = "Gradient"
        view.Background2 = [0.05, 0.05, 0.1]

    center = [(rest_bounds[0] + rest_bounds[1]) / 2, (rest_bounds[2] + rest_bounds[3]) / 2,
              (rest_bounds[4] + rest_bounds[5]) / 2]
    extent = max(rest_bounds[1] - rest_bounds[0], rest_bounds[3] - rest_bounds[2])
    if body.Floor:
        origin, p1, p2 = floor_plane_corners(body.FloorOrigin, body.FloorNormal, center,
                                             1.5 * extent)
        floor = pvs.Plane(registrationName="Floor", Origin=origin, Point1=p1, Point2=p2,
                          XResolution=12, YResolution=12)
        floor_display = pvs.Show(floor, view)
        floor_display.Representation = "Surface With Edges"
        floor_display.AmbientColor = floor_display.DiffuseColor = [0.75, 0.75, 0.72]
        floor_display.EdgeColor = [0.45, 0.45, 0.45]

    for obstacle in obstacles:
        obstacle_display = pvs.Show(obstacle, view)
        obstacle_display.AmbientColor = obstacle_display.DiffuseColor = [0.85, 0.55, 0.3]
        obstacle_display.Specular = 0.3

    # Where the body started: a faint wireframe of the input.
    ghost = pvs.Show(reader, view)
    ghost.Representation = "Wireframe"
    ghost.AmbientColor = ghost.DiffuseColor = [0.9, 0.9, 0.9]
    ghost.Opacity = 0.15

    # The body at the chosen frame, green with its surface triangles drawn (for the torus: the
    # skinned surface, not the particles). Colouring by VolumeRatio shows little at rest: the
    # sag under its own weight changes volumes by < 0.1 %.
    display = pvs.Show(pvs.OutputPort(body, port), view)
    # Solid color. (ColorBy(display, None) raises "invalid association string 'NONE'" in 5.11
    # when the display is not colored by an array yet.)
    display.ColorArrayName = ["POINTS", ""]
    display.Representation = "Surface With Edges"
    display.AmbientColor = display.DiffuseColor = [0.35, 0.78, 0.3]
    display.EdgeColor = [0.12, 0.35, 0.1]
    display.Specular = 0.4

    label = pvs.Text(registrationName="Label",
                     Text=f"Soft Body: {what}, t = {t_shot:.2f} s")
    label_display = pvs.Show(label, view)
    label_display.WindowLocation = "Upper Left Corner"
    label_display.FontSize = 14

    scene = pvs.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = t_shot
    view.ViewTime = t_shot

    # The first Render() of a session resets the camera (paraview.simple does that once): render
    # first, then place the camera.
    pvs.Render(view)
    # Camera: from the front-right, a little above the floor, looking at the rest position.
    distance = 4.3 * extent
    view.CameraFocalPoint = [center[0], center[1], 0.5 * center[2]]
    view.CameraPosition = [center[0] + 0.75 * distance, center[1] - distance,
                           0.5 * center[2] + 0.55 * distance]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraViewAngle = 30.0
    pvs.Render(view)
    pvs.SaveScreenshot(png, view, ImageResolution=list(args.size))
    print(f"demo: rendered in {time.perf_counter() - start:.1f} s", flush=True)

    # The scene as a ParaView state: the GUI opens it with the plugin loaded, ready to Play.
    pvs.SaveState(pvsm)

    # The animation: every frame rendered at the GIF's size, then assembled.
    animated = False
    if args.animation_width > 0:
        start = time.perf_counter()
        width = args.animation_width
        height = int(round(width * args.size[1] / args.size[0])) // 2 * 2
        rendered = []
        for k, t in enumerate(times):
            scene.AnimationTime = t
            view.ViewTime = t
            label.Text = f"Soft Body: {what}, t = {t:.2f} s"
            rendered.append(os.path.join(frames_dir, f"frame_{k:04d}.png"))
            pvs.SaveScreenshot(rendered[-1], view, ImageResolution=[width, height])
        animated = save_gif(rendered, gif, times[1] - times[0] if len(times) > 1 else 0.04)
        for f in rendered:
            os.remove(f)
        if animated:
            print(f"demo: animated {len(times)} frames in {time.perf_counter() - start:.1f} s",
                  flush=True)
        else:
            print("demo: python3-pil is missing: no animation (sudo apt-get install python3-pil)",
                  flush=True)
    # Destroy the render view now, while its X display and GLX context are alive. Left to
    # ParaView's finalization at interpreter exit, Debian's ParaView 5.11 under Xvfb fails in
    # X_GLXMakeCurrent (GLXBadContext) destroying it (3 runs of 3 without this line, 0 of 3
    # with it).
    pvs.Delete(view)
    del view

    # --- check and report ---------------------------------------------------------------------
    frame_files = sorted(f for f in os.listdir(frames_dir) if f.startswith(name + "_")) \
        if os.path.isdir(frames_dir) else []
    ok = True
    if not os.path.isfile(pvd) or len(frame_files) != len(times):
        print(f"demo: FAILED: expected {pvd} and {len(times)} frames in {frames_dir}, "
              f"found {len(frame_files)}", file=sys.stderr)
        ok = False
    if not os.path.isfile(png) or os.path.getsize(png) == 0:
        print(f"demo: FAILED: no image {png}", file=sys.stderr)
        ok = False
    if not os.path.isfile(pvsm):
        print(f"demo: FAILED: no state file {pvsm}", file=sys.stderr)
        ok = False
    if args.example != "torus":
        # No tet turned inside out in any frame (the frame cache makes the pass free). Bodies
        # landing on bodies under an implicit integrator (the pile) still invert a few where
        # they meet: they are held at each other's faces and load them by turns, not solved as
        # one system; up to 1 % is let pass there, as the unit tests of that landing do.
        allowed = 0 if args.example == "jelly" else 0.01
        inverted = []
        for t in times:
            body.UpdatePipeline(t)
            counts = body.GetClientSideObject().GetOutputDataObject(0).GetFieldData().GetArray(
                "InvertedTets")
            inverted.append(int(counts.GetTuple1(0)) if counts else 0)
        body.UpdatePipeline(t_shot)  # the frame the checks below read
        worst = max(range(len(times)), key=lambda k: inverted[k])
        print(f"demo: at most {inverted[worst]} tets inverted in a frame"
              + (f" (t = {times[worst]:g} s)" if inverted[worst] else ""))
        tets = body.GetClientSideObject().GetOutputDataObject(0).GetNumberOfCells()
        if inverted[worst] > allowed * tets:
            print(f"demo: FAILED: {inverted[worst]} of {tets} tets turned inside out "
                  f"(at most {int(allowed * tets)} allowed)", file=sys.stderr)
            ok = False
    size = rest_bounds[5] - rest_bounds[4]
    if args.example == "pile":
        import numpy as np
        from vtkmodules.util import numpy_support
        x = numpy_support.vtk_to_numpy(frame.GetPoints().GetData())
        b = PILE_BLOCK_BOUNDS
        inside = (x[:, 0] > b[0]) & (x[:, 0] < b[1]) & (x[:, 1] > b[2]) & (x[:, 1] < b[3]) & \
            (x[:, 2] > b[4]) & (x[:, 2] < b[5])
        on_block = (np.abs(x[:, 0]) < b[1]) & (np.abs(x[:, 1]) < b[3]) & (x[:, 2] >= b[5])
        print(f"demo: pile: {int(inside.sum())} points inside the block, {int(on_block.sum())} of "
              f"{len(x)} above it, lowest z {x[:, 2].min():.4f} m, highest {x[:, 2].max():.4f} m")
        if inside.any() or x[:, 2].min() < -1e-9:
            print("demo: FAILED: a body ended inside the block or below the floor", file=sys.stderr)
            ok = False
    # On the floor: within the collision margin above it (a tenth of the mean surface edge).
    elif body.Floor and list(body.FloorNormal) == [0.0, 0.0, 1.0] and \
            not (-0.01 * size <= bounds[4] - body.FloorOrigin[2] <= 0.03 * size):
        print(f"demo: FAILED: the body should rest on the floor at the end (lowest z "
              f"{bounds[4]:.4f} m)", file=sys.stderr)
        ok = False
    if args.example == "torus":
        # A torus that landed keeps its shape: the skinned surface is a rigid motion of the rest
        # surface up to a little sag (the best rotation by Kabsch's SVD, in the RMS sense).
        import numpy as np
        from vtkmodules.util import numpy_support
        rest = numpy_support.vtk_to_numpy(
            reader.GetClientSideObject().GetOutputDataObject(0).GetPoints().GetData()).astype(float)
        landed = numpy_support.vtk_to_numpy(shown.GetPoints().GetData()).astype(float)
        a, b = rest - rest.mean(axis=0), landed - landed.mean(axis=0)
        u, _, vt = np.linalg.svd(a.T @ b)
        rotation = u @ np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))]) @ vt
        diagonal = float(np.linalg.norm(rest.max(axis=0) - rest.min(axis=0)))
        off_rigid = float(np.sqrt(((a @ rotation - b) ** 2).sum(axis=1).mean())) / diagonal
        print(f"demo: torus: the landed surface is {100 * off_rigid:.2f} % of its diagonal (RMS) "
              f"off a rigid motion of its rest shape")
        if off_rigid > 0.02:
            print("demo: FAILED: the torus ended crushed (more than 2 % off a rigid motion)",
                  file=sys.stderr)
            ok = False
    parts = (["the floor"] if body.Floor else []) + \
        ([f"{len(obstacles)} obstacle" + ("s" if len(obstacles) > 1 else "")] if obstacles else [])
    print(f"demo: data:      {pvd} ({len(frame_files)} frames in {frames_dir}"
          + (f", with {' and '.join(parts)} in every frame)" if parts else ")"))
    print(f"demo: image:     {png}")
    if animated:
        print(f"demo: animation: {gif}")
    print(f"demo: state:     {pvsm}")
    print("demo: view the data with `paraview " + pvd + "` (no plugin needed); open the scene "
          "ready to Play with `PV_PLUGIN_PATH=" + os.path.dirname(os.path.abspath(args.plugin)) +
          " paraview --state=" + pvsm + "`")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
