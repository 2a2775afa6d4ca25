"""What the jelly demo (python.demo, scripts/demo.py) leaves for a user, opened as a user opens it:

- the .pvd: one frame per time step, each a multiblock of the body and the floor (a plane at the
  floor's height, spanning the body), readable without the plugin;
- the .pvsm: loaded into a fresh session with the plugin, it rebuilds the scene, and its Soft
  Body recomputes the run: its last frame equals the .pvd's last body frame bit for bit (the
  state holds every setting the run used);
- the .gif: one image per frame (checked where python3-pil is installed).

Run after python.demo (a CTest fixture), on its output folder (--demo-dir).
"""
import os

import numpy as np

import softbody_testing as sbt

args = sbt.parse_args(__doc__, lambda p: p.add_argument("--demo-dir", required=True))
pvd = os.path.join(args.demo_dir, "softbody.pvd")
pvsm = os.path.join(args.demo_dir, "softbody.pvsm")
gif = os.path.join(args.demo_dir, "softbody.gif")
for path in (pvd, pvsm):
    sbt.check(os.path.isfile(path), f"the demo wrote {path}")

import paraview.simple as pvs
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet

# The data, as `paraview softbody.pvd` opens it (no plugin loaded yet).
saved = pvs.PVDReader(FileName=pvd)
saved.UpdatePipelineInformation()
times = list(saved.TimestepValues)
sbt.check(len(times) > 10, f"the .pvd holds the frames ({len(times)})")
saved.UpdatePipeline(times[-1])
frame = saved.GetClientSideObject().GetOutputDataObject(0)
sbt.check(isinstance(frame, vtkMultiBlockDataSet) and frame.GetNumberOfBlocks() == 2,
          "each frame is a multiblock of the body and the floor")
# The PVD reader puts each part in a block of its own (a multiblock of the part's pieces).
body_part, floor_part = (frame.GetBlock(k).GetBlock(0) for k in range(2))
body_saved = sbt.points_of(body_part)
floor = sbt.points_of(floor_part)
print(f"pvd: {len(times)} frames; body {len(body_saved)} points; floor {len(floor)} points, "
      f"z in [{floor[:, 2].min():g}, {floor[:, 2].max():g}]")
sbt.check(floor_part.GetNumberOfCells() > 0 and np.ptp(floor[:, 2]) == 0.0,
          "the floor part is a flat plane")
sbt.check(floor[:, 0].min() <= body_saved[:, 0].min() and floor[:, 0].max() >= body_saved[:, 0].max(),
          "the floor spans the body")
sbt.check(abs(floor[0, 2] - body_saved[:, 2].min()) < 0.02,
          "the body rests on the saved floor at the end")
pvs.Delete(saved)

# The scene, as `paraview --state=softbody.pvsm` opens it with the plugin loaded.
pvs.LoadPlugin(args.plugin, remote=False)
pvs.LoadState(pvsm)
body = pvs.FindSource("SoftBody")
sbt.check(body is not None, "the state holds the Soft Body filter")
body.UpdatePipelineInformation()
sbt.check(np.allclose(list(body.TimestepValues), times, rtol=0, atol=1e-12),
          "the state's Soft Body advertises the .pvd's frame times")
recomputed = sbt.points_of(sbt.output_at(body, times[-1]))
worst = float(np.abs(recomputed - body_saved).max())
print(f"state: recomputed the run to t = {times[-1]:g} s; largest difference from the .pvd "
      f"{worst:.1e} m")
sbt.check(np.array_equal(recomputed, body_saved), "the state recomputes the saved run bit for bit")

try:
    from PIL import Image
except ImportError:
    print(f"python3-pil is missing: {gif} not checked")
else:
    sbt.check(os.path.isfile(gif), f"the demo wrote {gif}")
    with Image.open(gif) as animation:
        print(f"gif: {animation.n_frames} frames of {animation.size}")
        sbt.check(animation.n_frames == len(times), "the animation has one image per frame")
print("python.demo_outputs: all checks passed")
