"""The Athrill side, the physics' peer: the robot programs, in three parts. `mock/` is the Python mock of Athrill
and EV3RT a Python program runs on; `programs/` turns what `--app` names into a program of its kind and launches
it afresh for every test; `tuning/` makes the program each test's parameter values ask for. Beside them, the
builders of C programs (`native/`, `v850/`, `raspike_art/`) and the built-in programs (`apps/`). This root
imports nothing."""
