"""`python -m testctl.hako`: `hako` with this interpreter, as the tests and benchmark scripts start it."""

from testctl.hako.main import main

main()
