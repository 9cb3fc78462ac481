#include "qdmeta/tasks/rhex/gait_export.hpp"

#include <fmt/format.h>

#include <fstream>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/atomic_file.hpp"

namespace qdmeta::rhex {
namespace {

void require_poses(const EpisodeResult& episode) {
  if (episode.poses.empty()) throw InputError("gait export: the episode recorded no poses (set record_poses)");
}

// The page: frames as a JSON array of [t, x, y, z, roll, pitch, yaw, leg0..leg5]; geometry from
// docs/specification.md, RHex (body 0.54 x 0.39 x 0.139 m, hips, legs of diameter 0.154 m).
constexpr const char* kPage = R"HTML(<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>{title}</title>
<style>body{{font-family:sans-serif;margin:1em}} svg{{border:1px solid #ccc;background:#fcfcfc;display:block;margin:0.5em 0}}</style>
</head><body>
<h3>{title}</h3>
<div id="info"></div>
<svg id="side" width="960" height="260"></svg>
<svg id="top" width="960" height="260"></svg>
<script>
const frames = {frames};
const hipX = [-0.265, -0.015, 0.235, -0.265, -0.015, 0.235], hipY = [0.205, 0.2245, 0.205, -0.205, -0.2245, -0.205];
const L = 0.54, W = 0.39, H = 0.139, R = 0.077;
let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
for (const f of frames) {{ x0 = Math.min(x0, f[1]); x1 = Math.max(x1, f[1]); y0 = Math.min(y0, f[2]); y1 = Math.max(y1, f[2]); }}
x0 -= 0.6; x1 += 0.6;
const scale = Math.min(960 / (x1 - x0), 200 / Math.max(0.8, y1 - y0 + 0.8));
const sx = x => (x - x0) * scale, sz = z => 220 - z * scale, sy = y => 130 - (y - (y0 + y1) / 2) * scale;
const ns = 'http://www.w3.org/2000/svg';
function el(svg, tag, attrs) {{ const e = document.createElementNS(ns, tag); for (const k in attrs) e.setAttribute(k, attrs[k]); svg.appendChild(e); return e; }}
const side = document.getElementById('side'), topView = document.getElementById('top');
el(side, 'line', {{x1: 0, y1: sz(0), x2: 960, y2: sz(0), stroke: '#888'}});
el(topView, 'polyline', {{points: frames.map(f => sx(f[1]) + ',' + sy(f[2])).join(' '), fill: 'none', stroke: '#bbb'}});
const body = el(side, 'polygon', {{fill: '#4a7', stroke: '#254'}});
const legs = [0, 1, 2].map(() => el(side, 'path', {{fill: 'none', stroke: '#c52', 'stroke-width': 3}}));
const bodyTop = el(topView, 'polygon', {{fill: '#4a7', stroke: '#254'}});
// Side view: rotate (x, z) by pitch about y (x' = x cos + z sin, z' = -x sin + z cos).
function rot(x, z, a) {{ return [x * Math.cos(a) + z * Math.sin(a), -x * Math.sin(a) + z * Math.cos(a)]; }}
function draw(f) {{
  const [t, x, y, z, roll, pitch, yaw] = f;
  const corners = [[-L/2, -H/2], [L/2, -H/2], [L/2, H/2], [-L/2, H/2]].map(([a, b]) => rot(a, b, pitch));
  body.setAttribute('points', corners.map(([a, b]) => sx(x + a) + ',' + sz(z + b)).join(' '));
  for (let i = 0; i < 3; ++i) {{
    const [hx, hz] = rot(hipX[i], 0, pitch);
    let d = '';
    for (let k = 0; k <= 16; ++k) {{
      const s = Math.PI * k / 16, [px, pz] = rot(R * Math.sin(s), R * Math.cos(s) - R, pitch + f[7 + i]);
      d += (k ? 'L' : 'M') + sx(x + hx + px) + ',' + sz(z + hz + pz);
    }}
    legs[i].setAttribute('d', d);
  }}
  const c = Math.cos(yaw), s = Math.sin(yaw);
  bodyTop.setAttribute('points', [[-L/2, -W/2], [L/2, -W/2], [L/2, W/2], [-L/2, W/2]]
      .map(([a, b]) => sx(x + a * c - b * s) + ',' + sy(y + a * s + b * c)).join(' '));
  document.getElementById('info').textContent = `t = ${{t.toFixed(2)}} s   x = ${{x.toFixed(2)}} m   y = ${{y.toFixed(2)}} m   z = ${{z.toFixed(3)}} m`;
}}
let start = null;
function tick(now) {{
  if (start === null) start = now;
  const t = ((now - start) / 1000) % (frames[frames.length - 1][0] + 1);
  let i = 0;
  while (i + 1 < frames.length && frames[i + 1][0] <= t) ++i;
  draw(frames[i]);
  requestAnimationFrame(tick);
}}
requestAnimationFrame(tick);
</script>
<p>Side view (left legs, x forward, z up; the floor line is z = 0, obstacles are not drawn) and top view with the path. Written by qdmeta.</p>
</body></html>
)HTML";

}  // namespace

void write_gait_csv(const EpisodeResult& episode, const std::filesystem::path& path) {
  require_poses(episode);
  std::string text = "time,x,y,z,roll,pitch,yaw,leg_0,leg_1,leg_2,leg_3,leg_4,leg_5\n";
  for (const PoseRecord& p : episode.poses) {
    text += fmt::format("{}", p.time);
    for (double v : p.position) text += fmt::format(",{}", v);
    for (double v : p.euler) text += fmt::format(",{}", v);
    for (double v : p.legs) text += fmt::format(",{}", v);
    text += '\n';
  }
  write_file_atomic(path, text);
}

void write_gait_html(const EpisodeResult& episode, const std::filesystem::path& path, const std::string& title,
                     int stride) {
  require_poses(episode);
  if (stride < 1) throw InputError(fmt::format("gait export: stride = {} must be at least 1", stride));
  std::string frames = "[";
  for (std::size_t k = 0; k < episode.poses.size(); k += static_cast<std::size_t>(stride)) {
    const PoseRecord& p = episode.poses[k];
    frames += fmt::format("{}[{:.3f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}", k ? "," : "", p.time, p.position[0],
                          p.position[1], p.position[2], p.euler[0], p.euler[1], p.euler[2]);
    for (double v : p.legs) frames += fmt::format(",{:.4f}", v);
    frames += "]";
  }
  frames += "]";
  write_file_atomic(path, fmt::format(kPage, fmt::arg("title", title), fmt::arg("frames", frames)));
}

}  // namespace qdmeta::rhex
