"""CLI subcommands: each module defines NAME, HELP, add_arguments(parser) and run(args) -> int.

Register a new module in :data:`validation.cli.COMMAND_MODULES`.
"""
