"""Where a campaign's parameter sets come from: the search space and the optimizers that propose
points in it (GPyOpt, random, Optuna's). This root imports nothing."""
