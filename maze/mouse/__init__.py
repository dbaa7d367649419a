"""A user's own mouse program, unchanged, over mms's protocol: the lines it prints parsed into commands (`mms`),
the world that answers them and keeps its wall log (`mmsworld`), what it paints on the maze (`marks`), and the
child process it runs as (`harness`). This root imports nothing."""
