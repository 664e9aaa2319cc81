"""pivoting."""
