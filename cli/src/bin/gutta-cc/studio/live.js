// The studio's live script (docs/studio.md, "Simulate"): filled by the simulate work.
