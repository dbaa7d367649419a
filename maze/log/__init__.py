"""The wall log: the seed's 16-bit records and the append-only log of them (`wallrecord`), the maze a log
restores after a reset (`restore`), and the NOR flash model that weighs the log against a whole-maze snapshot
as a backup (`flash`). This root imports nothing."""
