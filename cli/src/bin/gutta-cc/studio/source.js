// The studio's source script (docs/studio.md, "STL and symbols"): filled by that work.
