// The studio's online script (docs/studio.md, "Online"): filled by the online work.
