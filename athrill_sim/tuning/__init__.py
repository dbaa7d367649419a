"""A program tuned as it is written: the forms a parameter takes (`forms/`, one module each) and their table
(`bindings`), the program each test's values make (`tune`), and what the forms find in a program: its ELF
globals (`elf_symbols`) and the cells of its command files (`command_files`). This root imports nothing."""
