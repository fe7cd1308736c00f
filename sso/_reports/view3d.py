"""An interactive 3D view in ``report.html``: a small canvas renderer, inline and offline.

:func:`scene_html` writes a ``<canvas>``, the scene as JSON and the renderer below
into the page: no library, no request to any host. The scene is a list of items in
model coordinates (mm):

* ``{"kind": "line", "points": [[x, y, z], ...], "colour", "width", "dash", "name"}``;
* ``{"kind": "point", "at": [x, y, z], "colour", "size", "name", "label"}``;
* ``{"kind": "face", "points": [[x, y, z], ...], "colour", "alpha", "name"}``;

with ``"centre"`` and ``"radius"`` (what to fit) and ``"yaw_deg"``, ``"pitch_deg"`` (the
first view). The view is orthographic: a turn about the vertical ``z`` axis (yaw), then
a tilt about the screen's horizontal (pitch). Drag turns it, the wheel zooms, a double
click returns to the first view, the arrow keys turn it too, and the name of the part
under the pointer is shown beside it. The canvas carries its view in ``data-yaw-deg``,
``data-pitch-deg`` and ``data-zoom``, so a test can see it turn.
"""

from __future__ import annotations

import html
import json
from collections.abc import Mapping
from typing import Any

VIEW_STYLE = """
.view3d { position: relative; display: inline-block; }
.view3d canvas { border: 1px solid #ddd; cursor: grab; touch-action: none; max-width: 100%; }
.view3d .tip { position: absolute; pointer-events: none; background: #fffbe6;
               border: 1px solid #999; padding: 0.1rem 0.4rem; font-size: 0.85rem;
               white-space: nowrap; }
"""

RENDERER = r"""
(function () {
  "use strict";
  var canvas = document.getElementById(VIEW_ID);
  var scene = JSON.parse(document.getElementById(VIEW_ID + "-data").textContent);
  var tip = document.getElementById(VIEW_ID + "-tip");
  var context = canvas.getContext("2d");
  var first = {yaw: scene.yaw_deg * Math.PI / 180, pitch: scene.pitch_deg * Math.PI / 180};
  var view = {yaw: first.yaw, pitch: first.pitch, zoom: 1};
  var drag = null;
  var limit = 89 * Math.PI / 180;

  function project(point) {
    var x = point[0] - scene.centre[0], y = point[1] - scene.centre[1];
    var z = point[2] - scene.centre[2];
    var cy = Math.cos(view.yaw), sy = Math.sin(view.yaw);
    var cp = Math.cos(view.pitch), sp = Math.sin(view.pitch);
    var across = cy * x - sy * y, along = sy * x + cy * y;
    var scale = view.zoom * Math.min(canvas.width, canvas.height) / (2.3 * scene.radius);
    return {x: canvas.width / 2 + scale * across,
            y: canvas.height / 2 - scale * (cp * z - sp * along),
            depth: cp * along + sp * z};
  }

  function mean(values) {
    return values.reduce(function (sum, value) { return sum + value; }, 0) / values.length;
  }

  function shapes() {
    var list = [];
    scene.items.forEach(function (item) {
      if (item.kind === "point") {
        var at = project(item.at);
        list.push({item: item, points: [at], depth: at.depth, order: 2});
      } else {
        var points = item.points.map(project);
        list.push({item: item, points: points, order: item.kind === "face" ? 0 : 1,
                   depth: mean(points.map(function (p) { return p.depth; }))});
      }
    });
    list.sort(function (a, b) { return b.depth - a.depth || a.order - b.order; });
    return list;
  }

  function draw() {
    context.clearRect(0, 0, canvas.width, canvas.height);
    context.fillStyle = "#ffffff";
    context.fillRect(0, 0, canvas.width, canvas.height);
    shapes().forEach(function (shape) {
      var item = shape.item, points = shape.points;
      context.save();
      context.strokeStyle = item.colour;
      context.fillStyle = item.colour;
      if (item.kind === "point") {
        context.beginPath();
        context.arc(points[0].x, points[0].y, item.size, 0, 2 * Math.PI);
        context.fill();
        if (item.label) {
          context.fillStyle = "#222222";
          context.font = "12px sans-serif";
          context.fillText(item.label, points[0].x + item.size + 3, points[0].y - 3);
        }
      } else {
        context.beginPath();
        context.moveTo(points[0].x, points[0].y);
        points.slice(1).forEach(function (p) { context.lineTo(p.x, p.y); });
        if (item.kind === "face") {
          context.closePath();
          context.globalAlpha = item.alpha;
          context.fill();
          context.globalAlpha = 1;
          context.lineWidth = 1;
          context.stroke();
        } else {
          context.lineWidth = item.width;
          context.setLineDash(item.dash ? [8, 5] : []);
          context.stroke();
        }
      }
      context.restore();
    });
    drawAxes();
    canvas.dataset.yawDeg = (view.yaw * 180 / Math.PI).toFixed(3);
    canvas.dataset.pitchDeg = (view.pitch * 180 / Math.PI).toFixed(3);
    canvas.dataset.zoom = view.zoom.toFixed(4);
  }

  function drawAxes() {
    var origin = {x: 40, y: canvas.height - 40};
    var cy = Math.cos(view.yaw), sy = Math.sin(view.yaw);
    var cp = Math.cos(view.pitch), sp = Math.sin(view.pitch);
    [["x", [1, 0, 0], "#d62728"], ["y", [0, 1, 0], "#2ca02c"], ["z", [0, 0, 1], "#1f77b4"]]
      .forEach(function (axis) {
        var v = axis[1];
        var across = cy * v[0] - sy * v[1], along = sy * v[0] + cy * v[1];
        var end = {x: origin.x + 25 * across, y: origin.y - 25 * (cp * v[2] - sp * along)};
        context.strokeStyle = axis[2];
        context.fillStyle = axis[2];
        context.lineWidth = 2;
        context.beginPath();
        context.moveTo(origin.x, origin.y);
        context.lineTo(end.x, end.y);
        context.stroke();
        context.font = "12px sans-serif";
        context.fillText(axis[0], end.x + 3, end.y);
      });
  }

  function segmentDistance(p, a, b) {
    var dx = b.x - a.x, dy = b.y - a.y, length = dx * dx + dy * dy;
    var t = length > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / length : 0;
    t = Math.max(0, Math.min(1, t));
    return Math.hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
  }

  function inside(p, polygon) {
    var found = false;
    for (var i = 0, j = polygon.length - 1; i < polygon.length; j = i++) {
      var a = polygon[i], b = polygon[j];
      if ((a.y > p.y) !== (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) {
        found = !found;
      }
    }
    return found;
  }

  function under(p) {
    var best = null, bestScore = Infinity;
    shapes().forEach(function (shape) {
      var item = shape.item, points = shape.points, score = Infinity;
      if (item.kind === "point") {
        var distance = Math.hypot(p.x - points[0].x, p.y - points[0].y);
        if (distance <= item.size + 4) { score = distance; }
      } else if (item.kind === "line") {
        for (var k = 1; k < points.length; k++) {
          var d = segmentDistance(p, points[k - 1], points[k]);
          if (d <= 5) { score = Math.min(score, 10 + d); }
        }
      } else if (inside(p, points)) {
        score = 100;
      }
      if (score < bestScore) { best = item; bestScore = score; }
    });
    return best;
  }

  function position(event) {
    var box = canvas.getBoundingClientRect();
    var left = event.clientX - box.left, top = event.clientY - box.top;
    return {x: (left - canvas.clientLeft) * canvas.width / canvas.clientWidth,
            y: (top - canvas.clientTop) * canvas.height / canvas.clientHeight,
            left: left, top: top};
  }

  canvas.addEventListener("pointerdown", function (event) {
    drag = {x: event.clientX, y: event.clientY};
    canvas.style.cursor = "grabbing";
    if (canvas.setPointerCapture) {
      try { canvas.setPointerCapture(event.pointerId); } catch (ignored) { /* synthetic */ }
    }
  });
  canvas.addEventListener("pointermove", function (event) {
    if (drag) {
      view.yaw += (event.clientX - drag.x) * 0.01;
      view.pitch = Math.max(-limit, Math.min(limit, view.pitch + (event.clientY - drag.y) * 0.01));
      drag = {x: event.clientX, y: event.clientY};
      tip.hidden = true;
      draw();
      return;
    }
    var p = position(event), item = under(p);
    if (item) {
      tip.textContent = item.name;
      tip.style.left = (p.left + 14) + "px";
      tip.style.top = (p.top + 10) + "px";
      tip.hidden = false;
    } else {
      tip.hidden = true;
    }
  });
  function release() { drag = null; canvas.style.cursor = "grab"; }
  canvas.addEventListener("pointerup", release);
  canvas.addEventListener("pointercancel", release);
  canvas.addEventListener("pointerleave", function () { tip.hidden = true; });
  canvas.addEventListener("wheel", function (event) {
    event.preventDefault();
    view.zoom = Math.max(0.2, Math.min(20, view.zoom * Math.exp(-event.deltaY * 0.001)));
    draw();
  }, {passive: false});
  canvas.addEventListener("dblclick", function () {
    view.yaw = first.yaw; view.pitch = first.pitch; view.zoom = 1;
    draw();
  });
  canvas.addEventListener("keydown", function (event) {
    var turns = {ArrowLeft: [-0.1, 0], ArrowRight: [0.1, 0], ArrowUp: [0, -0.1],
                 ArrowDown: [0, 0.1]}[event.key];
    if (!turns) { return; }
    event.preventDefault();
    view.yaw += turns[0];
    view.pitch = Math.max(-limit, Math.min(limit, view.pitch + turns[1]));
    draw();
  });
  draw();
})();
"""


def scene_html(scene: Mapping[str, Any], caption: str, identifier: str) -> str:
    """The HTML of one interactive view: canvas, tooltip, scene JSON and renderer.

    Parameters
    ----------
    scene : mapping
        Items, centre, radius and first view (module notes).
    caption : str
        Shown under the view (escaped here).
    identifier : str
        The canvas's element id, unique in the page (letters, digits, ``-``).
    """
    # "</" could close the script element early; "<\/" is the same JSON string.
    data = json.dumps(scene, allow_nan=False).replace("</", "<\\/")
    label = html.escape(caption, quote=True)
    script = RENDERER.replace("VIEW_ID", json.dumps(identifier))
    return (f'<figure class="view3d"><canvas id="{identifier}" width="960" height="620" '
            f'tabindex="0" role="img" aria-label="{label}"></canvas>'
            f'<div class="tip" id="{identifier}-tip" hidden></div>'
            f"<figcaption>{label}</figcaption>"
            f'<script type="application/json" id="{identifier}-data">{data}</script>'
            f"<script>{script}</script></figure>")
