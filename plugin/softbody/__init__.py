"""SoftBody's Python helpers, importable in pvpython and pvbatch once the plugin is loaded.

`from softbody import sweep`: run time against error on the user's own mesh and scene
(softbody/sweep.py)."""
