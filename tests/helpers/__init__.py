"""What the tests of several areas share: commands, processes, paths, builds and doubles."""
