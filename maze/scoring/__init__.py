"""Results held against the true maze: what a restored log or a mouse's belief got right (`compare`, `mazelog
diff`), and mice and built-in strategies over many mazes (`benchmark`, `mazelog bench`). This root imports
nothing."""
