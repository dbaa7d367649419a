"""The physics side (the paper's "Unity" role): the MuJoCo world, the lap task, the sensor and actuator
model, the sync modes with Athrill, and the process that serves tests over the mapped files."""
