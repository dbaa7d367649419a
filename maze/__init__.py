"""mazelog, which stands apart from the bench: micromouse wall logs, the mazes they are of, and the searches that
write them, one folder per concept. `log/` is the wall log itself; `files/` the maze files and their formats;
`search/` the built-in mouse searching a maze; `fastpath/` the fastest run through the walls known; `timing/` the
time model both price moves with; `mouse/` a user's own mouse program over mms's protocol; `pictures/` mazes and
replays drawn; `scoring/` a result against the true maze, and mice and strategies over many mazes. The root
keeps what the folders share: the maze (`model`) and its directions (`direction`), the error base (`errors`),
writing a file whole or not at all (`outputs`), and the `mazelog` command that joins them (`cli`); `data/` holds
the shipped mazes, mice and example log. This root imports nothing."""
