"""`hako`, the user's command: the top of the stack, beside `testctl`'s own command line, which only parses,
checks and launches, and which nothing imports. The commands are in `main`; this root imports nothing."""
