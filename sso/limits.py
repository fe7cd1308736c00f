"""Every physical limit and default of sso, defined once.

Nothing here imports anything from sso: every other layer may import it.
"""

MAX_STARTS = 10_000
"""Most start points one design run accepts (a bound on memory and time)."""
