"""CLI subcommands: each module defines NAME, add_arguments(parser) and run(args) -> int (and, optionally,
needs_jax(args) -> bool).

Register a new module in :data:`validation.cli.SUBCOMMANDS` (its name and one-line help: the parser lists
every command from there without importing it) and :func:`validation.cli.command_module` (an import
statement, not a name).  Modules that are not subcommands: :mod:`.release`, the ``python -m
gear_rattle.validation.commands.release`` entry of the certified post-release duration (docs/release.md),
with its own ``main(argv)``; :mod:`.trackimpl` (run as a command by ``--impl``); the helpers
:mod:`.transient_common`, ``_check_common`` (what check's two modes share: the run composed of
:mod:`validation.golden.scoring` and its reports), ``_check_orbits`` and ``_check_suite``.
"""
