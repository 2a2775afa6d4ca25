"""SoftBody's Python helpers, importable in pvpython and pvbatch once the plugin is loaded.

`from softbody import sweep`: run time against error on the user's own mesh and scene
(softbody/sweep.py).
`from softbody import keyframes`: the changes made to Soft Body Conditions during playback as
animation keyframes, to replay and save (softbody/keyframes.py)."""
