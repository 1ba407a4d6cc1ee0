"""One module per pipeline stage; each is a library function the CLI command wraps."""
