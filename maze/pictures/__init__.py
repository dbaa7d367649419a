"""Mazes drawn: a maze in one fixed palette (`render`) and a replay record by record, as a PNG or a GIF film
(`film`). This root imports nothing."""
