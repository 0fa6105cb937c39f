"""docs/isf-gallery.md (made by docs/isf_gallery.py) shows every shader issv ships, with its thumbnail."""
from pathlib import Path

from effects.isf.effect import shipped

DOCS = Path(__file__).resolve().parents[2] / "docs"


def test_every_shipped_shader_has_a_row_and_a_thumbnail():
    gallery = (DOCS / "isf-gallery.md").read_text()
    for name in shipped():
        assert f"| `{name}` |" in gallery, f"{name} missing: run python docs/isf_gallery.py"
        assert (DOCS / "images" / "isf" / f"{Path(name).name}.png").is_file(), name
