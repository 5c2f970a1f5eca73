"""CLI subcommands: each module defines NAME, HELP, add_arguments(parser) and run(args) -> int.

Register a new module in :func:`validation.cli.command_modules` (an import statement, not a name).  One module is not a subcommand:
:mod:`.release` is the ``python -m gear_rattle.validation.commands.release`` entry of the certified
post-release duration (docs/release.md), with its own ``main(argv)``.
"""
