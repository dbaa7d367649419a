"""The Python mock of Athrill and EV3RT, the process a Python robot program runs in (`main`, `athrill-sim`): the
kernel's virtual clock and its lockstep with the physics (`kernel`), the guest memory over the mapped files
(`bus`), and EV3RT's C API with the brick's devices (`ev3api`, `ev3brick`, `ev3fs`, `ev3lcd`, `ev3serial`,
`ev3types`). The native C runtime (`athrill_sim.native`) mirrors it call for call. This root imports nothing."""
