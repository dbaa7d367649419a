"""`hako`, the user's command: the top layer, which only parses, checks and launches, and which
nothing imports. The commands are in `main`; this root imports nothing."""
