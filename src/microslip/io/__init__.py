"""Input and output: ranges, TOML configuration and atomic file writing."""
