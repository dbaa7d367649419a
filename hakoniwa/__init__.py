"""hakoniwa: the test bench. Importing it pins the floating-point kernels first (`hakoniwa.wire.numerics`),
before anything of ours imports numpy, so every process of a campaign computes alike on every machine."""

from hakoniwa.wire.numerics import pin_kernels

pin_kernels()
