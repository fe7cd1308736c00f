"""From a case to its result document (a JSON-ready dictionary), one module per kind."""
