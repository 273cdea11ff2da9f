"""The exit codes of every `hivex` command, in a module of their own so each command module can import them."""

EXIT_OK, EXIT_FAIL, EXIT_USAGE = 0, 1, 2
EXIT_INTERRUPTED = 128 + 2  # what a shell reports for a command ended by SIGINT
EXIT_PIPE = 128 + 13  # what a shell reports for a writer ended by SIGPIPE
