"""Every report file rendered from a result document alone; ``sso.write_report``."""
