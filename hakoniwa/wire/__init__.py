"""The contract every process of the bench shares: the mapped files' layout, waiting on them, the run
directory, simulated time, exit statuses and the capped copy of a child process's output (mazelog uses that
too). Standard library only, so that any process (or a user's own controller) can import it without MuJoCo
or NumPy."""
