"""The tests, one package per area, so that `from tests.helpers.commands import hako` names one module
wherever pytest or a child process imports it."""
