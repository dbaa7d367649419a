"""`python -m hakoniwa.cli`: `hako` with this interpreter, as the tests and benchmark scripts start it."""

from hakoniwa.cli.main import main

main()
