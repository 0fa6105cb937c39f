"""FAKE of Nuitrack's PyNuitrack package (tests only, see ../README.md)."""
