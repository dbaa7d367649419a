"""The time model: the mouse a time is estimated for (`mouseparams`, `--timing`), how long its straights, turns
and search take (`motion`), and a fastest run as the commands print it (`route`). The search and the fast path
both price moves with it. This root imports nothing."""
