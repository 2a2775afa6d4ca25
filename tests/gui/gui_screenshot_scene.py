"""One screenshot scene, run inside the real ParaView GUI by scripts/gui_screenshots.sh (through
tests/gui/run_gui.sh; see gui_support.py). SOFTBODY_GUI_SCENE picks the scene:

- jelly: data/jelly.vtu, Soft Body with the defaults (Mass-Spring), as Apply shows it, at the
  squash after landing, the colour range of Velocity set over all frames;
- torus: data/torus.vtp voxelized, Soft Body with Method XPBD and the torus as its Surface input
  (chosen in the panel's Surface combo box), the skinned Surface shown instead of the lattice;
- convergence: the cloth under XPBD with its Convergence port in a Line Chart View beside the
  render view (Residual against Iteration).

The scenes follow the README's "Using it in the ParaView GUI" walk-through step by step, so the
pictures show what those steps give. Every scene still fails on a message in Output Messages.
"""
import os
import sys

sys.path.insert(0, os.environ["SOFTBODY_GUI_DIR"])
import gui_support  # noqa: E402

failures = []
try:
    messages = gui_support.OutputMessages()
    from paraview.simple import (AssignViewToLayout, CreateView, GetActiveView,
                                 GetAnimationScene, GetDisplayProperties, GetLayout,
                                 OutputPort, Render, SetActiveSource, SetActiveView,
                                 XMLPolyDataReader, XMLUnstructuredGridReader)
    gui_support.load_plugin(globals())
    scene_name = os.environ["SOFTBODY_GUI_SCENE"]
    view = GetActiveView()

    def look_at(center, distance):
        # From the front, a little from the right and above, so the floor reads as a floor.
        view.CameraFocalPoint = center
        view.CameraPosition = [center[0] + 0.55 * distance, center[1] - distance,
                               center[2] + 0.45 * distance]
        view.CameraViewUp = [0.0, 0.0, 1.0]

    def go_to(body, time):
        scene = GetAnimationScene()
        scene.UpdateAnimationUsingDataTimeSteps()
        scene.AnimationTime = time

    if scene_name == "jelly":
        reader = XMLUnstructuredGridReader(FileName=[gui_support.data_file("jelly.vtu")])
        gui_support.apply_like_gui(reader)
        body = SoftBody(Input=reader, EndTime=1.0)
        gui_support.apply_like_gui(body)
        mesh = GetDisplayProperties(OutputPort(body, 0), view)
        mesh.RescaleTransferFunctionToDataRangeOverTime()
        mesh.SetScalarBarVisibility(view, True)
        go_to(body, 0.32)
        look_at([0.0, 0.0, 0.25], 1.6)
        SetActiveSource(body)
    elif scene_name == "torus":
        torus = XMLPolyDataReader(FileName=[gui_support.data_file("torus.vtp")])
        gui_support.apply_like_gui(torus)
        lattice = SoftBodyVoxelize(Input=torus, Resolution=20)
        gui_support.apply_like_gui(lattice)
        body = SoftBody(Input=lattice, Surface=torus, Method="XPBD", Restitution=0.2,
                        EndTime=1.0)
        gui_support.apply_like_gui(body)
        # The README's step: click the Surface eye, then the Mesh eye.
        gui_support.click_eye(body, 3, view, True)
        gui_support.click_eye(body, 0, view, False)
        go_to(body, 0.4)
        look_at([0.0, 0.0, 0.3], 2.0)
        SetActiveSource(body)
    elif scene_name == "convergence":
        cloth = SoftBodyCloth(Resolution=[30, 30])
        gui_support.apply_like_gui(cloth)
        body = SoftBody(Input=cloth, Method="XPBD", PinnedPointsArray="Pinned",
                        Iterations=20, EndTime=1.0)
        gui_support.apply_like_gui(body)
        GetDisplayProperties(OutputPort(body, 0), view).RescaleTransferFunctionToDataRangeOverTime()
        go_to(body, 0.6)
        look_at([0.0, 0.3, 0.4], 3.6)
        # The README's step: split the view, pick Line Chart View, click the Convergence eye.
        chart = CreateView("XYChartView")
        AssignViewToLayout(view=chart, layout=GetLayout(view), hint=2)
        SetActiveView(chart)
        residual = gui_support.click_eye(body, 2, chart, True)
        if residual is None or residual.GetXMLName() != "XYChartRepresentation":
            failures.append("the Convergence eye in a Line Chart View gave %s"
                            % (residual.GetXMLName() if residual else None))
        if gui_support.click_eye(body, 2, view, True) is not None:
            failures.append("the Convergence eye in the render view showed something")
        residual = GetDisplayProperties(OutputPort(body, 2), chart)
        residual.UseIndexForXAxis = 0
        residual.XArrayName = "Iteration"
        residual.SeriesVisibility = ["Residual"]
        chart.LeftAxisLogScale = 1
        Render(chart)
        SetActiveView(view)
        SetActiveSource(body)
    else:
        raise ValueError("unknown SOFTBODY_GUI_SCENE %r" % scene_name)
    Render(view)
    gui_support.finish_later(failures, messages, wait_s=5.0, shot=os.environ["SOFTBODY_GUI_SHOT"])
except Exception:
    gui_support.fail_now(failures)
