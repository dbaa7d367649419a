"""The built-in mouse searching a true maze with the Adachi method and writing its wall log (`explorer`): its
strategies, offered without loading the search (`strategies`), its step maps (`stepmap`) and dead-end closing
(`closing`). The fastest run it may stop for is `maze.fastpath`'s. This root imports nothing."""
