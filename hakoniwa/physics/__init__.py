"""The physics side (the paper's "Unity" role): the MuJoCo world, the tasks (the lap), the sensor and actuator
model, the sync modes with Athrill, and the server that runs tests over the mapped files."""
