"""A parameter-search campaign: its loop, configuration, objective, journal, Optuna study,
progress line, reports, validation, best.patch and dashboard. This root imports nothing, so
that `config` and `journal` (read by `--help` and `hako test`) come without the loop's NumPy."""
