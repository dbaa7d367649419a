"""The kinds of robot program, one module each, all implementing `kind.ProgramKind`: a Python program on the
mock (`python`), an EV3RT C or C++ program compiled for this machine (`native`, SPIKE programs too), the same
built into a v850 image for the real emulator (`image`), and a v850 image as it is (`elf`).
`athrill_sim.programs.resolve` looks them up in one table. This root imports nothing."""
