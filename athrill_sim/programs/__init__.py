"""A robot program from what `--app` names to a fresh process for every test: the kinds of program (`kinds/`,
one module each) and the table that finds the one an `--app` is (`resolve`), the `Program` they make
(`program`), the build cache their builders share (`build_cache`) and where those builders' pieces come from
(`third_party`), the real emulator's command line (`athrill2`), a Python program's own source files
(`python_sources`), and the launch: one process per test (`launcher`), forked from a zygote for the mock
(`zygote`), a native program in its own working folder (`working_folder`). The builders themselves stay beside
it (`athrill_sim.native`, `athrill_sim.v850`, `athrill_sim.raspike_art`). This root imports nothing."""
