"""Maze files: the common text format (`mazefile`), mms's `.num` and the classic binary `.maz`
(`mazeformats`), the one reader and writer that picks a format by suffix (`mazeio`), a JSON view for other
tools (`mazejson`), and the contest mazes shipped in `maze/data/mazes` (`builtin`). This root imports nothing."""
