"""Ends a ParaView GUI started by run_gui.sh (see gui_support.finish_later).

Usage (pvpython): gui_finish.py <paraview pid> <seconds to wait> [<screenshot.png>]
Waits while the GUI paints, grabs the ParaView window from the X screen (DISPLAY) into the PNG
when one is given, then kills the GUI. Pillow's ImageGrab reads the X server directly, so the picture is the real
window: panels, pipeline browser and views as a user sees them.
"""
import os
import signal
import sys
import time

pid, wait_s = int(sys.argv[1]), float(sys.argv[2])
shot = sys.argv[3] if len(sys.argv) > 3 else ""
time.sleep(wait_s)
try:
    if shot:
        from PIL import ImageGrab
        screen = ImageGrab.grab()
        # The window does not fill the virtual screen: crop the black screen around it, and
        # store 256 colours (a GUI has few), which keeps the committed PNGs small.
        window = screen.crop(screen.convert("L").getbbox())
        window.quantize(colors=256).save(shot, optimize=True)
finally:
    # SIGKILL, not SIGTERM: the verdict is already written, and ParaView answers SIGTERM with a
    # fatal-signal stack trace in its log, which would read as a failure.
    os.kill(pid, signal.SIGKILL)
