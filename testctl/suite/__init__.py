"""`hako test`: a test file's named cases, run on the benches, judged against their expectations
and reported (table, JSON, JUnit XML). This root imports nothing."""
