"""Interactive parts of the report: a recorded run played back in the page, and the robots
as rotatable 3D models.

* :func:`record_run` simulates one run (``swarm_sim``) with a frame recorder and returns its
  trajectory as a small JSON-able record (cm, s, rad; modes by name; the run's events with
  their captions). :func:`player_html` is the page fragment that plays it: top view and side
  view on canvases, play/pause, step, scrub, speed, event marks on the scrub bar (seed chosen,
  landing, releases, switches, retreat, target found), and a click on a robot shows its state.
  Plain JavaScript, no library.
* :func:`model_html` shows GLB models (from ``cubot_cad``) with three.js, vendored from the
  npm registry into ``vendor/`` (classic scripts: the report is opened from disk, where
  Chromium refuses module imports; the GLB is embedded as base64 for the same reason).

Both fragments report script errors into ``document.body.dataset.vcErrors`` and expose
``window.vcPlayer`` / ``window.vcModels`` so a headless browser can check them.
"""

from __future__ import annotations

import base64
import html
import json
import shutil
from pathlib import Path

VENDOR = Path(__file__).parent / "vendor" / "three-0.147.0"
THREE_FILES = ("three.min.js", "GLTFLoader.js", "OrbitControls.js", "LICENSE")
MAX_FRAMES = 900
MAX_VALUES = 2_000_000  # robots x frames: keeps the page a few MB at most
MAX_GLB_BYTES = 40 * 2**20


def record_run(preset: str, robots: int, void_width: int, seed: int, limits: str = "derived",
               every_s: float = 0.5, **overrides) -> dict:
    """Simulate one run, recording a frame every ``every_s`` simulated seconds; the trajectory
    record the player reads. Raises the simulator's InputError on bad input."""
    from swarm_sim.render import CAPTIONS, COLOURS, MODE_NAMES, Recorder, caption
    from swarm_sim.runner import resolve_params, simulate

    p = resolve_params(preset, robots, void_width, limits, **overrides)
    rec = Recorder(every_s=every_s)
    state, res = simulate(p, seed, on_step=rec)
    frames = rec.frames
    cap = max(2, min(MAX_FRAMES, MAX_VALUES // max(1, p.robots)))
    if len(frames) > cap:  # evenly thinned, the last frame kept
        step = len(frames) / (cap - 1)
        frames = [frames[int(k * step)] for k in range(cap - 1)] + [frames[-1]]
    events = []
    for t, kind, r, data in state.events:
        c = caption((t, kind, r, data))
        if c is not None:
            events.append([round(float(t), 2), kind, int(r), c, bool(CAPTIONS[kind][1])])
    return {
        "schema": 1, "preset": p.preset, "robots": p.robots, "void_width": p.void_width, "seed": int(seed),
        "limits": p.limits_source, "end_reason": res.end_reason, "success": res.success,
        "arena_cm": [p.arena_w_cm, p.arena_h_cm], "void_cm": [p.void_x0_cm, p.void_x1_cm],
        "target_cm": [p.target_x_cm, p.target_y_cm, p.target_radius_cm],
        "obstacles_cm": [list(map(float, o)) for o in p.obstacles],
        "robot_cm": [p.robot_length_cm, p.robot_width_cm],
        "modes": {str(int(m)): MODE_NAMES[m] for m in MODE_NAMES},
        "colours": {str(int(m)): c for m, c in COLOURS.items()},
        "t_s": [round(f.t_s, 2) for f in frames],
        "x_cm": [[round(float(v), 1) for v in f.x] for f in frames],
        "y_cm": [[round(float(v), 1) for v in f.y] for f in frames],
        "h_rad": [[round(float(v), 3) for v in f.h] for f in frames],
        "mode": [[int(v) for v in f.mode] for f in frames],
        "state": [[int(v) for v in f.state] for f in frames],
        "layer": [[int(v) for v in (f.layer if f.layer is not None else [0] * len(f.x))] for f in frames],
        "events": events[:2000],
    }


def _json_script(elem_id: str, data) -> str:
    text = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    return f'<script type="application/json" id="{elem_id}">{text}</script>'


ERRORS_JS = """<script>(function(){var b=document.body;b.dataset.vcErrors=b.dataset.vcErrors||"";
window.addEventListener("error",function(e){var t=e.target&&e.target!==window?(e.target.src||e.target.href||e.target.tagName):"";
b.dataset.vcErrors+=(e.message||("failed to load "+t))+" | ";},true);})();</script>"""

PLAYER_CSS = """
.vc-player{border:1px solid #ccc;padding:8px;margin:1em 0;background:#fafafa}
.vc-player canvas{display:block;background:#fff;border:1px solid #ddd;max-width:100%;cursor:crosshair}
.vc-controls{display:flex;gap:6px;align-items:center;margin:6px 0;flex-wrap:wrap}
.vc-range{display:block;width:100%;margin:0;box-sizing:border-box}
.vc-marks{position:relative;height:14px;margin:0 8px 4px}
.vc-marks span{position:absolute;top:0;width:3px;height:12px;background:#d62728;cursor:pointer}
.vc-info{font:12px monospace;white-space:pre;min-height:3em}
.vc-caption{font-size:0.9em;color:#444;min-height:1.3em}
.vc-legend span{display:inline-block;margin-right:10px;font-size:0.85em}
.vc-legend i{display:inline-block;width:10px;height:10px;margin-right:3px;vertical-align:middle}
.vc-model{border:1px solid #ccc;margin:1em 0;width:100%;height:420px;display:block;background:#f4f6f8}
"""

PLAYER_JS = r"""
(function(){
var root=document.getElementById("vc-player"); if(!root) return;
var D=JSON.parse(document.getElementById("vc-run").textContent);
var top=root.querySelector(".vc-top"), side=root.querySelector(".vc-side");
var tc=top.getContext("2d"), sc=side.getContext("2d");
var n=D.t_s.length, k=0, playing=false, speed=1, sel=-1, last=0, acc=0;
var W=D.arena_cm[0], H=D.arena_cm[1], L=D.robot_cm[0], Wr=D.robot_cm[1];
var pad=6, s=(top.width-2*pad)/W; top.height=Math.round(H*s+2*pad);
var range=root.querySelector(".vc-range"); range.max=n-1;
var label=root.querySelector(".vc-time"), info=root.querySelector(".vc-info"), cap=root.querySelector(".vc-caption");
function X(x){return pad+x*s} function Y(y){return top.height-pad-y*s}
function drawTop(){
  var c=tc; c.clearRect(0,0,top.width,top.height);
  c.strokeStyle="#000"; c.lineWidth=1.5; c.strokeRect(X(0),Y(H),W*s,H*s);
  c.fillStyle="#000"; c.fillRect(X(D.void_cm[0]),Y(H),(D.void_cm[1]-D.void_cm[0])*s,H*s);
  c.fillStyle="#1f3fff"; c.beginPath(); c.arc(X(D.target_cm[0]),Y(D.target_cm[1]),Math.max(2,D.target_cm[2]*s),0,7); c.fill();
  c.fillStyle="#d62728"; D.obstacles_cm.forEach(function(o){c.beginPath(); c.arc(X(o[0]),Y(o[1]),o[2]*s,0,7); c.fill();});
  var x=D.x_cm[k], y=D.y_cm[k], h=D.h_rad[k], m=D.mode[k], ly=D.layer[k];
  var order=x.map(function(_,i){return i}).sort(function(a,b){return ly[a]-ly[b]});
  order.forEach(function(i){
    c.save(); c.translate(X(x[i]),Y(y[i])); c.rotate(-h[i]);
    c.fillStyle=D.colours[m[i]]||"#999"; c.globalAlpha=ly[i]>0?0.75:1;
    c.fillRect(-L*s/2,-Wr*s/2,L*s,Wr*s); c.globalAlpha=1;
    c.strokeStyle=i===sel?"#ff00ff":"#000"; c.lineWidth=i===sel?2.5:0.5; c.strokeRect(-L*s/2,-Wr*s/2,L*s,Wr*s);
    c.restore();
  });
}
function drawSide(){
  var c=sc, x0=D.void_cm[0], x1=D.void_cm[1], reach=Math.max(25*L,x1-x0);
  var a=Math.max(0,x0-reach), b=Math.min(W,x1+reach), ss=(side.width-2*pad)/(b-a), g=side.height*0.6, hh=0.85*L*ss;
  function SX(v){return pad+(v-a)*ss}
  c.clearRect(0,0,side.width,side.height);
  c.fillStyle="#c8b48a"; c.fillRect(SX(a),g,(x0-a)*ss,side.height-g); c.fillRect(SX(x1),g,(b-x1)*ss,side.height-g);
  var x=D.x_cm[k], m=D.mode[k], ly=D.layer[k];
  for(var i=0;i<x.length;i++){
    var inS=(m[i]==3||m[i]==1), z=Math.max(0,ly[i]);
    if(x[i]<a-L||x[i]>b+L) continue;
    if(inS){var over=!(x[i]+L/2<=x0||x[i]-L/2>=x1); c.fillStyle=over?"#e377c2":"#9467bd";
      c.fillRect(SX(x[i]-L/2),g-(z+1)*hh,L*ss,hh); c.strokeStyle=i===sel?"#ff00ff":"#000"; c.lineWidth=i===sel?2:0.5;
      c.strokeRect(SX(x[i]-L/2),g-(z+1)*hh,L*ss,hh);}
    else{c.fillStyle=D.colours[m[i]]||"#999"; c.beginPath(); c.arc(SX(x[i]),g-hh/2,2,0,7); c.fill();}
  }
}
function counts(){var m=D.mode[k], out={}; m.forEach(function(v){out[v]=(out[v]||0)+1});
  return Object.keys(out).map(function(v){return D.modes[v]+" "+out[v]}).join("   ");}
function showInfo(){
  if(sel<0){info.textContent="click a robot to see its state"; return;}
  var st=D.state[k][sel];
  info.textContent="robot "+sel+": "+D.modes[D.mode[k][sel]]+"\nx "+D.x_cm[k][sel].toFixed(1)+" cm, y "+
    D.y_cm[k][sel].toFixed(1)+" cm, heading "+(D.h_rad[k][sel]*180/Math.PI).toFixed(0)+" deg\n"+
    (st>0?"structure position "+st+(D.layer[k][sel]>0?", layer "+D.layer[k][sel]:""):"thesis state "+st);
}
function showCaption(){var t=D.t_s[k], out=[]; D.events.forEach(function(e){if(e[0]<=t&&e[0]>t-4)out.push("t="+e[0].toFixed(1)+" s  "+e[3])});
  cap.textContent=out.slice(-3).join("  \u00b7  ");}
function draw(){drawTop(); drawSide(); range.value=k;
  label.textContent="t = "+D.t_s[k].toFixed(1)+" s  (frame "+(k+1)+"/"+n+")   "+counts(); showInfo(); showCaption();
  root.dataset.frame=k;}
function seek(i){k=Math.max(0,Math.min(n-1,i|0)); draw();}
// a timer, not requestAnimationFrame: 10 frames per second of page time at 1x (frames are 0.5 s of
// simulated time apart, so 1x plays at 5x real time), and it also runs in a headless browser
function tick(){ if(!playing) return; var ts=performance.now(), dt=last?(ts-last)/1000:0; last=ts; acc+=dt*speed*10;
  if(acc>=1){var st=Math.floor(acc); acc-=st; if(k+st>=n-1){seek(n-1); pause(); return;} seek(k+st);}
  timer=setTimeout(tick,50);}
var timer=null;
function play(){if(k>=n-1)k=0; playing=true; last=0; btn.textContent="pause"; clearTimeout(timer); tick();}
function pause(){playing=false; btn.textContent="play";}
var btn=root.querySelector(".vc-play");
btn.onclick=function(){playing?pause():play()};
root.querySelector(".vc-back").onclick=function(){pause(); seek(k-1)};
root.querySelector(".vc-fwd").onclick=function(){pause(); seek(k+1)};
root.querySelector(".vc-speed").onchange=function(e){speed=parseFloat(e.target.value)};
range.oninput=function(){pause(); seek(parseInt(range.value))};
top.onclick=function(ev){var r=top.getBoundingClientRect(), px=(ev.clientX-r.left)*top.width/r.width,
  py=(ev.clientY-r.top)*top.height/r.height, cx=(px-pad)/s, cy=(top.height-pad-py)/s, best=-1, bd=1e9;
  D.x_cm[k].forEach(function(x,i){var d=Math.hypot(x-cx,D.y_cm[k][i]-cy); if(d<bd){bd=d;best=i}});
  sel=bd<=L?best:-1; draw();};
var marks=root.querySelector(".vc-marks"), tmax=D.t_s[n-1]||1;
D.events.filter(function(e){return e[4]}).slice(0,300).forEach(function(e){var sp=document.createElement("span");
  sp.style.left=(100*e[0]/tmax)+"%"; sp.title="t="+e[0].toFixed(1)+" s: "+e[3];
  sp.onclick=function(){pause(); var i=0; while(i<n-1&&D.t_s[i]<e[0])i++; seek(i)}; marks.appendChild(sp);});
var leg=root.querySelector(".vc-legend");
Object.keys(D.modes).forEach(function(m){var sp=document.createElement("span"); sp.innerHTML='<i style="background:'+D.colours[m]+'"></i>'+D.modes[m]; leg.appendChild(sp)});
window.vcPlayer={n:n, frame:function(){return k}, seek:seek, play:play, pause:pause,
  select:function(i){sel=i; draw()}, info:function(){return info.textContent}, marks:marks.children.length};
draw();
if(root.dataset.autoplay==="1") play();
})();
"""


def player_html(run: dict, autoplay: bool = False) -> str:
    """The page fragment that plays ``run`` (a :func:`record_run` record)."""
    title = (f"{run['preset']}, {run['robots']} robots, {run['void_width']}-wide void, seed {run['seed']}, "
             f"{run['limits']} limits: {run['end_reason']}")
    return (f"<style>{PLAYER_CSS}</style>{ERRORS_JS}"
            f'<div class="vc-player" id="vc-player" data-autoplay="{int(autoplay)}">'
            f"<div><b>{html.escape(title)}</b></div>"
            '<canvas class="vc-top" width="1100" height="500"></canvas>'
            '<div class="vc-controls"><button class="vc-play">play</button><button class="vc-back">&#9664; step</button>'
            '<button class="vc-fwd">step &#9654;</button>'
            '<select class="vc-speed"><option value="0.5">0.5x</option><option value="1" selected>1x</option>'
            '<option value="4">4x</option><option value="16">16x</option></select><span class="vc-time"></span></div>'
            '<input class="vc-range" type="range" min="0" value="0">'
            '<div class="vc-marks" title="events"></div><div class="vc-caption"></div>'
            '<canvas class="vc-side" width="1100" height="150"></canvas>'
            '<div class="vc-legend"></div><div class="vc-info"></div></div>'
            + _json_script("vc-run", run) + f"<script>{PLAYER_JS}</script>")


MODEL_JS = r"""
(function(){
var cvs=document.querySelectorAll("canvas.vc-model"); window.vcModels={count:cvs.length, drawn:0};
cvs.forEach(function(cv){
  var renderer=new THREE.WebGLRenderer({canvas:cv, antialias:true, preserveDrawingBuffer:true});
  renderer.setPixelRatio(window.devicePixelRatio||1); renderer.setSize(cv.clientWidth||800, cv.clientHeight||420, false);
  var scene=new THREE.Scene(); scene.background=new THREE.Color(0xf4f6f8);
  var cam=new THREE.PerspectiveCamera(35,(cv.clientWidth||800)/(cv.clientHeight||420),0.1,1e6);
  scene.add(new THREE.HemisphereLight(0xffffff,0x667788,1.0)); scene.add(new THREE.AmbientLight(0xffffff,0.35));
  var dl=new THREE.DirectionalLight(0xffffff,0.9);
  dl.position.set(1,2,3); scene.add(dl);
  var ctl=new THREE.OrbitControls(cam,cv); ctl.addEventListener("change",function(){renderer.render(scene,cam)});
  var b64=document.getElementById(cv.dataset.glb).textContent.trim(), bin=atob(b64), buf=new Uint8Array(bin.length);
  for(var i=0;i<bin.length;i++) buf[i]=bin.charCodeAt(i);
  new THREE.GLTFLoader().parse(buf.buffer,"",function(g){
    // CAD colours are plain paints: no metal (a metallic PBR surface renders black without an environment map)
    g.scene.traverse(function(o){if(o.material){[].concat(o.material).forEach(function(m){if("metalness" in m){m.metalness=0; m.roughness=0.75;}})}});
    scene.add(g.scene); var box=new THREE.Box3().setFromObject(g.scene), c=box.getCenter(new THREE.Vector3()),
    r=box.getSize(new THREE.Vector3()).length()||1;
    cam.position.set(c.x+0.9*r,c.y+0.6*r,c.z+0.9*r); cam.near=r/1000; cam.far=r*100; cam.updateProjectionMatrix();
    ctl.target.copy(c); ctl.update(); renderer.render(scene,cam);
    var gl=renderer.getContext(), px=new Uint8Array(4*64*64), w=gl.drawingBufferWidth, h=gl.drawingBufferHeight;
    gl.readPixels(Math.max(0,(w>>1)-32),Math.max(0,(h>>1)-32),64,64,gl.RGBA,gl.UNSIGNED_BYTE,px);
    var lit=0; for(var j=0;j<px.length;j+=4){if(Math.abs(px[j]-244)+Math.abs(px[j+1]-246)+Math.abs(px[j+2]-248)>30) lit++;}
    cv.dataset.drawn=lit; if(lit>0) window.vcModels.drawn++;
  },function(e){document.body.dataset.vcErrors+="GLB: "+e+" | ";});
});
})();
"""


def copy_vendor(out: Path) -> str:
    """Copy three.js beside the report; returns the directory relative to ``out``."""
    dst = Path(out) / "vendor" / VENDOR.name
    dst.mkdir(parents=True, exist_ok=True)
    for f in THREE_FILES:
        shutil.copyfile(VENDOR / f, dst / f)
    return f"vendor/{VENDOR.name}"


def model_html(glbs: list[tuple[str, bytes]], vendor_rel: str) -> str:
    """Rotatable 3D views of GLB models (``(caption, glb bytes)``), three.js from ``vendor_rel``."""
    parts = [f"<style>{PLAYER_CSS}</style>{ERRORS_JS}"]
    for k, (caption, data) in enumerate(glbs):
        parts.append(f'<figure><canvas class="vc-model" data-glb="vc-glb-{k}" width="900" height="420"></canvas>'
                     f"<figcaption>{html.escape(caption)} (drag to rotate, wheel to zoom)</figcaption></figure>"
                     f'<script type="text/plain" id="vc-glb-{k}">{base64.b64encode(data).decode()}</script>')
    parts += [f'<script src="{vendor_rel}/{f}"></script>' for f in THREE_FILES[:3]]
    parts.append(f"<script>{MODEL_JS}</script>")
    return "".join(parts)


def find_glbs(cad_dir: Path | None, limit: int = 6) -> list[tuple[str, bytes]]:
    """The GLB models under ``cad_dir`` (``cubot_cad`` writes one per robot and docked bridge)."""
    if not cad_dir or not Path(cad_dir).is_dir():
        return []
    out = []
    for p in sorted(Path(cad_dir).rglob("*.glb"))[:limit]:
        if p.stat().st_size <= MAX_GLB_BYTES and p.read_bytes()[:4] == b"glTF":
            out.append((p.relative_to(cad_dir).as_posix(), p.read_bytes()))
    return out
