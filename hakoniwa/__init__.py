"""The ground of the Hakoniwa-style test bench, a stack of packages, bottom to top (`tests/project/test_layers.py`
holds each module to importing only its own package and those below it):

1. `hakoniwa.wire`: the contract every process shares, standard library only.
2. `hakoniwa.conventions`: what every command line shares.
3. `hakoniwa.physics`: the "Unity" side, which starts the Athrill it is given for each test; and beside it, its
   peer `athrill_sim` (its own package): the program side, resolving, building and running the robot program.
4. `testctl` (its own package): the controller, tests, campaigns and benches, where the two peers meet.
5. `testctl.hako`: the user's `hako`, imported by nothing.

This root imports only `hakoniwa.wire.numerics` (standard library), so that a process that needs only the wire
contract does not load MuJoCo. It pins the floating-point kernels before anything of ours imports numpy, so
that every process of a campaign computes alike on every x86-64 machine with AVX2.
"""

from hakoniwa.wire.numerics import pin_kernels

pin_kernels()
