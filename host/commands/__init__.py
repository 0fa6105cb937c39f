"""One module per `issv` subcommand (discovered by host.cli)."""
