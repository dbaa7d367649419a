"""The contract every process of the bench shares: the mapped files' layout, waiting on them, the run
directory, simulated time and exit statuses. Standard library only, so that any process (or a user's own
controller) can import it without MuJoCo or NumPy."""
