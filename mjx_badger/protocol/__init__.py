"""How the thesis was run: the thesis-code and thesis-text protocols, every difference a named field
(protocols), and the on-robot conditions sim, office and outdoor (conditions). It may import estimation and below."""
