"""Helpers for scripts that run inside the real ParaView GUI (paraview --script=...).

Shared by tests/gui/test_gui_smoke.py and scripts/gui_screenshots.py. The scripts are started
by tests/gui/run_gui.sh, which passes everything through environment variables (a --script gets
no arguments): SOFTBODY_PLUGIN_FILE, SOFTBODY_DATA_DIR, SOFTBODY_GUI_RESULT (the file the
verdict is written to) and, for screenshots, SOFTBODY_GUI_SHOT (the PNG to write).

Why the pieces look the way they do:
- A --script runs on the GUI's main thread before the Qt event loop paints anything. So the
  script does its pipeline work and checks, writes its verdict, and `finish_later` starts a
  helper process that waits while the event loop paints, grabs the screen and ends the GUI.
- Apply in the GUI (pqApplyBehavior::showData) calls ShowInPreferredView for every output port
  with the active view, which is where the proxy's <Hints> decide what is shown and where;
  `apply_like_gui` makes the same calls, so the hints are exercised as on a click on Apply.
- Messages that reach the Output Messages window go through the GUI's vtkOutputWindow; an
  observer on it counts every error and warning.
"""
import os
import subprocess
import traceback

from paraview import servermanager
from paraview.modules.vtkRemotingViews import vtkSMParaViewPipelineControllerWithRendering
from paraview.simple import (GetActiveView, GetAnimationScene, LoadPlugin, Render,
                             SetActiveSource, SetActiveView)
from vtkmodules.vtkCommonCore import vtkOutputWindow

ENV = os.environ


class OutputMessages:
    """Records what reaches the GUI's output window (the Output Messages window)."""

    def __init__(self):
        self.window = vtkOutputWindow.GetInstance()
        self.events = []
        for event in ("ErrorEvent", "WarningEvent"):
            self.window.AddObserver(event, self._record)

    def _record(self, obj, event):
        self.events.append(event)


def load_plugin(namespace):
    """Loads the plugin; its filters become functions in `namespace` (the caller's globals)."""
    plugin = ENV["SOFTBODY_PLUGIN_FILE"]
    LoadPlugin(plugin, remote=False, ns=namespace)
    return plugin


def data_file(name):
    return os.path.join(ENV["SOFTBODY_DATA_DIR"], name)


def apply_like_gui(source):
    """Shows `source` as the GUI's first Apply does; returns {port: view XML name or None}."""
    controller = vtkSMParaViewPipelineControllerWithRendering()
    active = GetActiveView()
    shown = {}
    for port in range(source.SMProxy.GetNumberOfOutputPorts()):
        view = controller.ShowInPreferredView(source.SMProxy, port,
                                              active.SMProxy if active else None)
        if view is not None:
            controller.AssignViewToLayout(view, None, 0)
        shown[port] = view.GetXMLName() if view is not None else None
    # The GUI hides the inputs of a filter shown in the same view (replace_input, default on).
    if hasattr(source, "Input") and active is not None:
        for prop in ("Input", "Surface"):
            upstream = source.GetPropertyValue(prop) if source.GetProperty(prop) else None
            if upstream is not None:
                controller.Hide(upstream.SMProxy, 0, active.SMProxy)
    SetActiveSource(source)
    if active is not None:
        SetActiveView(active)
        active.ResetCamera()
    return shown


def click_eye(source, port, view, visible):
    """What a click on an output port's eye in the Pipeline Browser does with `view` active
    (pqPipelineBrowserWidget::setVisibility): returns the representation, or None when the view
    cannot show that port (a table in a render view)."""
    controller = vtkSMParaViewPipelineControllerWithRendering()
    return controller.SetVisibility(source.SMProxy, port, view.SMProxy, visible)


def visible_ports(source, view):
    """The output ports of `source` with a visible representation in `view`."""
    controller = vtkSMParaViewPipelineControllerWithRendering()
    return [port for port in range(source.SMProxy.GetNumberOfOutputPorts())
            if controller.GetVisibility(source.SMProxy, port, view.SMProxy)]


def _end_gui_after(wait_s, shot=None):
    """Starts the helper that ends the GUI (see finish_later)."""
    helper = os.path.join(os.path.dirname(os.path.abspath(__file__)), "gui_finish.py")
    log = open(ENV["SOFTBODY_GUI_RESULT"] + ".finish.log", "w")
    # No empty argument: pvpython cannot decode one and crashes.
    command = [ENV.get("SOFTBODY_PVPYTHON", "pvpython"), helper, str(os.getpid()), str(wait_s)]
    subprocess.Popen(command + ([shot] if shot else []), stdout=log, stderr=subprocess.STDOUT)


def finish_later(failures, messages, wait_s=4.0, shot=None):
    """Writes the verdict, then lets the GUI paint for `wait_s` s before it is ended.

    The verdict file says PASS when `failures` is empty and nothing reached Output Messages.
    The end comes from a helper process (gui_finish.py, in pvpython): ParaView has no Python call
    to quit, and a Python thread would never run, since the GUI's interpreter keeps the GIL
    while the event loop runs. The helper grabs the X screen into `shot` (a PNG) if given, then
    kills the GUI; run_gui.sh also fails on any error or warning ParaView logged meanwhile.
    """
    if messages.events:
        failures.append("%d message(s) reached the Output Messages window: %s"
                        % (len(messages.events), ", ".join(messages.events)))
    verdict = "PASS\n" if not failures else "FAIL\n" + "\n".join(failures) + "\n"
    with open(ENV["SOFTBODY_GUI_RESULT"], "w") as result:
        result.write(verdict)
    print(verdict, flush=True)
    _end_gui_after(wait_s, shot)


def fail_now(failures):
    """Writes the verdict at once (an exception in the script) and has ParaView ended the same
    way as after a verdict (no os._exit: the script returns, the helper ends the GUI)."""
    failures.append(traceback.format_exc())
    with open(ENV["SOFTBODY_GUI_RESULT"], "w") as result:
        result.write("FAIL\n" + "\n".join(failures) + "\n")
    print("FAIL\n" + "\n".join(failures), flush=True)
    _end_gui_after(0.0)
