"""The interactive 3D view's HTML: self-contained, escaped, and drawn from the scene.

The browser test (test_column_view_browser.py) runs it; these need no browser.
"""

from __future__ import annotations

import json
import re

from sso._reports.view3d import scene_html

SCENE = {"items": [{"kind": "point", "at": [0.0, 0.0, 0.0], "colour": "#000000", "size": 4.0,
                    "name": "a </script><b> name", "label": "P0"}],
         "centre": [0.0, 0.0, 0.0], "radius": 1.0, "yaw_deg": 10.0, "pitch_deg": 20.0}


def test_nothing_in_the_scene_or_caption_can_close_its_script():
    text = scene_html(SCENE, "a </script><b> caption", "view-1")
    assert "</script><b>" not in text
    assert "a &lt;/script&gt;&lt;b&gt; caption" in text
    data = text.split('id="view-1-data">')[1].split("</script>")[0]
    assert json.loads(data) == SCENE


def test_the_view_asks_no_host_for_anything():
    text = scene_html(SCENE, "caption", "view-1")
    assert re.search(r"https?:|//[a-z]|src=|import\(|fetch\(|XMLHttpRequest", text) is None

