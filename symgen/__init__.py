"""symgen: symbolic models of general constrained robots."""
