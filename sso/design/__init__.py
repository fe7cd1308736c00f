"""Design problems: options, bounds, starts, the objective and its CasADi NLP."""
