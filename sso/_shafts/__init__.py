"""The Hooke-joint shaft series: the design, its figures of merit, its NLP and its optimiser."""
