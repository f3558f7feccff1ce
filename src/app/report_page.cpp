// The page skeleton and the three page kinds (report_page.h).
#include "app/report_page.h"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include "app/report_charts.h"
#include "app/report_format.h"
#include "app/report_pictures.h"
#include "app/report_sections.h"

namespace rayes {
namespace {
using json = nlohmann::json;

// Inline so that the page needs nothing else. The script (a) records script errors and
// charts without a drawn mark into #page-check, which the browser test reads
// (tests/app/report_browser_test.cpp), and (b) shows the value under the cursor.
const char* kStyle =
    "body{font:14px/1.4 system-ui,sans-serif;margin:1.5em;color:#222}h1{font-size:1.4em;margin:0 0 .3em}"
    "h2{font-size:1.1em;margin-top:1.4em;border-bottom:1px solid #ccc}table{border-collapse:collapse}"
    "td,th{padding:2px 10px;text-align:left;vertical-align:top}th{border-bottom:1px solid #999}"
    ".num{text-align:right;font-variant-numeric:tabular-nums}tr.data:nth-child(even){background:#f3f3f3}"
    ".skip{color:#777}.note{color:#666}.warn{color:#b00;font-weight:bold}figure{display:inline-block;vertical-align:top;margin:.4em 2em .6em 0}"
    "figcaption{font-weight:600;margin-bottom:2px}svg.chart{font:11px system-ui,sans-serif;overflow:visible}"
    "svg .grid{stroke:#e4e4e4}svg .axisline{stroke:#888}svg .axis{fill:#555}svg .note{fill:#666}"
    "svg .outlier{fill:#d03030;font-size:12px}svg .pointlabel{fill:#333;font-size:10px}svg .mark:hover{opacity:.7}"
    ".runs{display:flex;gap:2em;overflow-x:auto;align-items:flex-start}.run{flex:0 0 auto;border-left:3px solid #ddd;padding-left:1em}"
    ".run.outlier{border-left-color:#d03030}img.preview{min-width:24em;max-width:48em;image-rendering:pixelated;border:1px solid #ccc}"
    "#readout{position:fixed;pointer-events:none;background:#222;color:#fff;padding:2px 6px;border-radius:3px;"
    "font-size:12px;display:none}td.ratio{font-weight:600}"
    ".pictures{display:flex;flex-wrap:wrap;gap:1em}canvas.picture{image-rendering:pixelated;border:1px solid #ccc;cursor:crosshair}"
    ".legendrow{display:flex;gap:.4em;align-items:center;font-size:12px}.pixel-readout{font:12px monospace;min-height:1.3em}"
    "figure.heatfigure{max-width:40em}figure.heatfigure .note{font-size:12px}";
const char* kScript =
    "(function(){var errors=[];"
    // The heat maps (app/report_pictures.h): a viridis ramp, values as little-endian float32.
    "var V=[[68,1,84],[72,40,120],[62,74,137],[49,104,142],[38,130,142],[31,158,137],[53,183,121],[109,205,89],"
    "[180,222,44],[253,231,37]];"
    "function ramp(t){t=Math.max(0,Math.min(1,t));var x=t*(V.length-1),i=Math.min(V.length-2,Math.floor(x)),f=x-i;"
    "return [0,1,2].map(function(c){return Math.round(V[i][c]+(V[i+1][c]-V[i][c])*f)});}"
    "function bytesOf(b){var s=atob(b),a=new Uint8Array(s.length);for(var i=0;i<s.length;i++)a[i]=s.charCodeAt(i);return a;}"
    "function fmt(v){return isNaN(v)?'no surface':String(Number(v.toPrecision(6)));}"
    "function drawPictures(check){var pics=document.querySelectorAll('canvas.picture'),bad=[];"
    "pics.forEach(function(cv){var w=cv.width,h=cv.height,raw=bytesOf(cv.getAttribute('data-values')),"
    "ctx=cv.getContext('2d'),img=ctx.createImageData(w,h),d=img.data,n=w*h,ok;"
    "if(cv.classList.contains('beauty')){ok=raw.length==3*n;for(var i=0;ok&&i<n;i++){d[4*i]=raw[3*i];"
    "d[4*i+1]=raw[3*i+1];d[4*i+2]=raw[3*i+2];d[4*i+3]=255;}}"
    "else{var v=new Float32Array(raw.buffer,0,raw.length>>2),hi=+cv.getAttribute('data-max');cv.values=v;ok=v.length==n;"
    "for(var i=0;ok&&i<n;i++){var c=isNaN(v[i])?[200,200,200]:ramp(hi>0?v[i]/hi:0);"
    "d[4*i]=c[0];d[4*i+1]=c[1];d[4*i+2]=c[2];d[4*i+3]=255;}}"
    "if(ok)ctx.putImageData(img,0,0);else bad.push(cv.getAttribute('data-layer'));"
    "cv.addEventListener('mousemove',function(e){var r=cv.getBoundingClientRect(),"
    "x=Math.floor((e.clientX-r.left)*w/r.width),y=Math.floor((e.clientY-r.top)*h/r.height);"
    "if(x<0||y<0||x>=w||y>=h)return;"
    "cv.closest('.pictures').querySelectorAll('canvas.picture').forEach(function(o){"
    "var t=o.closest('figure').querySelector('.pixel-readout');"
    "t.textContent='x '+x+', y '+y+(o.values?': '+fmt(o.values[y*w+x])+(o.getAttribute('data-unit')||''):'');});});});"
    "document.querySelectorAll('canvas.legend').forEach(function(l){var c=l.getContext('2d');"
    "for(var x=0;x<l.width;x++){var k=ramp(x/(l.width-1));c.fillStyle='rgb('+k.join(',')+')';c.fillRect(x,0,1,l.height);}});"
    "check.setAttribute('data-pictures',String(pics.length));"
    "if(bad.length){check.setAttribute('data-status','fail');check.setAttribute('data-empty',"
    "check.getAttribute('data-empty')+' pictures: '+bad.join(','));}"
    // #probe=LAYER,X,Y: a mousemove over pixel (X, Y) of that picture, as a user's (the browser test).
    "var m=/probe=([a-z]+),([0-9]+),([0-9]+)/.exec(location.hash);"
    "if(m){var cv=document.querySelector('canvas.picture[data-layer='+m[1]+']');if(cv){var r=cv.getBoundingClientRect();"
    "cv.dispatchEvent(new MouseEvent('mousemove',{bubbles:true,clientX:r.left+(+m[2]+0.5)*r.width/cv.width,"
    "clientY:r.top+(+m[3]+0.5)*r.height/cv.height}));}}}"
    "window.addEventListener('error',function(e){errors.push(String(e.message||e))});"
    "window.addEventListener('load',function(){"
    "var charts=document.querySelectorAll('svg.chart'),empty=[];"
    "charts.forEach(function(c,i){var drawn=0;c.querySelectorAll('.mark').forEach(function(m){"
    "var b=m.getBBox();if(b.width>0&&b.height>0)drawn++;});"
    "if(!drawn){var f=c.parentNode.querySelector('figcaption');empty.push(i+': '+(f?f.textContent:''));}});"
    "var d=document.createElement('div');d.id='page-check';d.hidden=true;"
    "d.setAttribute('data-charts',String(charts.length));d.setAttribute('data-empty',empty.join('; '));"
    "d.setAttribute('data-errors',errors.join('; '));"
    "d.setAttribute('data-status',errors.length||empty.length||!charts.length?'fail':'ok');"
    "document.body.appendChild(d);"
    "try{drawPictures(d);}catch(x){d.setAttribute('data-status','fail');d.setAttribute('data-errors',String(x));}"
    // #only=ID: the page's title and that part alone (a link to one chart; the docs' screenshots),
    // hidden after the check above measured every chart.
    "var only=/only=([a-z-]+)/.exec(location.hash),keep=only&&document.getElementById(only[1]);"
    "if(keep)Array.prototype.forEach.call(document.body.children,function(c){"
    "if(c!==keep&&c.tagName!='H1'&&c!==d)c.style.display='none';});"
    "var r=document.createElement('div');r.id='readout';document.body.appendChild(r);"
    "document.addEventListener('mousemove',function(e){var t=e.target;"
    "if(t&&t.classList&&t.classList.contains('mark')){var n=t.querySelector('title');"
    "r.textContent=n?n.textContent:'';r.style.display='block';r.style.left=(e.clientX+12)+'px';"
    "r.style.top=(e.clientY+12)+'px';}else r.style.display='none';});});})();";

std::string shortName(const StatsFile& f) { return std::filesystem::path(f.path).filename().string(); }

// Robust outliers: beyond 3 scaled median absolute deviations of the median (1.4826 · MAD is
// the standard deviation of a normal sample), so that one slow frame cannot hide itself by
// inflating the spread as it would a mean ± 3σ rule. With no spread (MAD 0) nothing is marked,
// and nothing within 10 % of the median is: files that agree to a few percent (39 dicings
// against 40) have a tiny MAD that would otherwise mark a difference nobody would look at.
std::vector<bool> outliersOf(const std::vector<double>& v) {
  std::vector<bool> out(v.size(), false);
  if (v.size() < 3) return out;
  const auto median = [](std::vector<double> x) {
    std::sort(x.begin(), x.end());
    const size_t n = x.size();
    return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
  };
  const double m = median(v);
  std::vector<double> dev;
  for (double x : v) dev.push_back(std::fabs(x - m));
  const double mad = median(dev);
  if (!(mad > 0)) return out;
  const double bound = std::max(3 * 1.4826 * mad, 0.1 * std::fabs(m));
  for (size_t i = 0; i < v.size(); ++i) out[i] = std::fabs(v[i] - m) > bound;
  return out;
}

std::string jobSummary(const std::vector<StatsFile>& runs, std::vector<bool>& anyOutlier) {
  struct Figure {
    const char* title;
    const char* pointer;
    const char* unit;
  };
  static const Figure figures[] = {{"Render time (wall clock, s)", "/totals/time_s/total", " s"},
                                   {"Run time (wall clock, s)", "/totals/time_s/wall", " s"},
                                   {"Dice + bottom (thread time, s)", nullptr, " s"},
                                   {"Peak resident memory", "/totals/peak_rss_bytes", " B"},
                                   {"Dicings", "/totals/leaves_diced", ""},
                                   {"Rays", "/totals/rays", ""},
                                   {"Rays per dicing", "/totals/rays_per_dicing", ""}};
  std::ostringstream o;
  o << "<h2>The files side by side</h2><p>A red column (&#9650;) is an outlier: more than 3 scaled median absolute "
       "deviations and more than 10 % from the files' median.</p>";
  anyOutlier.assign(runs.size(), false);
  for (const Figure& f : figures) {
    ColumnChart c{f.title, f.unit, {}, {{f.title, {}}}};
    for (const StatsFile& r : runs) {
      c.categories.push_back(shortName(r));
      c.series[0].values.push_back(f.pointer ? number(r.stats, f.pointer)
                                             : number(r.stats, "/totals/time_s/dice") + number(r.stats, "/totals/time_s/bottom"));
    }
    c.outliers = outliersOf(c.series[0].values);
    for (size_t i = 0; i < runs.size(); ++i) anyOutlier[i] = anyOutlier[i] || c.outliers[i];
    o << columnChart(c);
  }
  bool errors = false;
  for (const StatsFile& r : runs) errors = errors || finalRmse(r.stats) > 0;
  if (errors) {
    LineChart c{"Error against time (log-log), every file", "seconds", "RMSE", true, true};
    for (const StatsFile& r : runs) {
      if (!r.stats.contains("error_vs_time")) continue;
      Line l{shortName(r), {}};
      for (const json& e : r.stats["error_vs_time"])
        l.points.push_back({e["time_s"].get<double>(), e["rmse"].get<double>(), e["spp"].dump() + " spp"});
      if (!l.points.empty()) c.lines.push_back(l);
    }
    o << lineChart(c);
  }
  return o.str();
}

}  // namespace

std::string pageSkeleton(const std::string& title, const std::string& body) {
  return std::string("<!DOCTYPE html><html lang=en><head><meta charset=utf-8><title>") + htmlEscape(title) +
         "</title><style>" + kStyle + "</style><script>" + kScript + "</script></head><body>" + body + "</body></html>\n";
}

std::string reportPage(const std::vector<StatsFile>& runs, const std::string& previewPng, const CostPictures* pictures,
                       const std::string& picturesNote) {
  std::ostringstream o;
  if (runs.size() == 1) {
    const json& s = runs[0].stats;
    o << "<h1>rayes report: " << htmlEscape(methodTitle(s)) << "</h1>" << runSummary(s);
    if (pictures) o << picturesSection(*pictures);
    else if (!previewPng.empty()) o << "<p><img class=preview alt=preview src=\"data:image/png;base64," << base64(previewPng) << "\"></p>";
    if (!picturesNote.empty()) o << "<p class=warn>" << htmlEscape(picturesNote) << "</p>";
    o << runSections(s);
    return pageSkeleton("rayes report: " + methodTitle(s) + ", " + s["scene"]["file"].get<std::string>(), o.str());
  }
  std::string methods;
  for (const StatsFile& r : runs) {
    const std::string m = methodTitle(r.stats);
    if (methods.find(m) == std::string::npos) methods += (methods.empty() ? "" : ", ") + m;
  }
  o << "<h1>rayes report: " << runs.size() << " runs, " << htmlEscape(methods) << "</h1><ol>";
  for (const StatsFile& r : runs) o << "<li>" << htmlEscape(r.path) << ": " << runSummary(r.stats) << "</li>";
  o << "</ol>";
  std::vector<bool> outlier;
  o << jobSummary(runs, outlier) << "<h2>Every run</h2><div class=runs>";
  for (size_t i = 0; i < runs.size(); ++i)
    o << "<section class=\"run" << (outlier[i] ? " outlier" : "") << "\"><h1>" << htmlEscape(shortName(runs[i]))
      << (outlier[i] ? " <span class=warn>outlier</span>" : "") << "</h1>" << runSummary(runs[i].stats)
      << runSections(runs[i].stats) << "</section>";
  o << "</div>";
  return pageSkeleton("rayes report: " + std::to_string(runs.size()) + " runs", o.str());
}

std::string comparisonPage(const StatsFile& a, const StatsFile& b) {
  const json &A = a.stats, &B = b.stats;
  std::ostringstream o;
  o << "<h1>rayes comparison: " << htmlEscape(methodTitle(A)) << " against " << htmlEscape(methodTitle(B)) << "</h1>"
    << "<p>A = " << htmlEscape(a.path) << "</p>" << runSummary(A) << "<p>B = " << htmlEscape(b.path) << "</p>" << runSummary(B)
    << "<p>Ratios are B / A: below 1, B took less.</p>";
  const auto table = [&](const std::string& title, const std::vector<std::tuple<std::string, double, double>>& rows, bool isBytes) {
    o << "<h2>" << htmlEscape(title) << "</h2><table><tr><th></th><th class=num>A</th><th class=num>B</th><th class=num>B / A</th></tr>";
    for (const auto& [name, x, y] : rows)
      o << "<tr class=data><td>" << htmlEscape(name) << "</td><td class=num>" << (isBytes ? shortBytes(x) : shortNumber(x, 4))
        << "</td><td class=num>" << (isBytes ? shortBytes(y) : shortNumber(y, 4)) << "</td><td class=\"num ratio\">"
        << ratioText(x, y) << "</td></tr>";
    o << "</table>";
    ColumnChart c{title + ": A and B", isBytes ? " B" : "", {}, {{"A", {}}, {"B", {}}}, false};
    for (const auto& [name, x, y] : rows) {
      c.categories.push_back(name);
      c.series[0].values.push_back(x);
      c.series[1].values.push_back(y);
    }
    o << columnChart(c);
  };
  std::vector<std::tuple<std::string, double, double>> wall, thread, memory, work;
  const auto wa = wallStages(A), wb = wallStages(B), ta = threadStages(A), tb = threadStages(B);
  for (size_t i = 0; i < wa.size(); ++i) wall.push_back({wa[i].name, wa[i].seconds, wb[i].seconds});
  for (size_t i = 0; i < ta.size(); ++i) thread.push_back({ta[i].name, ta[i].seconds, tb[i].seconds});
  json owners = A["memory"]["by_owner"];
  owners.update(B["memory"]["by_owner"]);
  for (const auto& [k, v] : owners.items()) {
    const std::string p = "/memory/by_owner/" + k;
    memory.push_back({k, number(A, p.c_str()), number(B, p.c_str())});
  }
  memory.push_back({"peak resident", number(A, "/totals/peak_rss_bytes"), number(B, "/totals/peak_rss_bytes")});
  for (const char* k : {"rays", "shadow_rays", "leaves_diced", "grid_cache_hits", "micropolygons_created", "rays_per_dicing"}) {
    const std::string p = std::string("/totals/") + k;
    work.push_back({k, number(A, p.c_str()), number(B, p.c_str())});
  }
  table("Wall clock (seconds)", wall, false);
  table("Thread time, summed over threads (seconds)", thread, false);
  table("Memory by owner", memory, true);
  table("Work: rays and dicings", work, false);
  if (finalRmse(A) > 0 || finalRmse(B) > 0) {
    o << "<h2>Error</h2><p>Final RMSE: A " << shortNumber(finalRmse(A), 4) << ", B " << shortNumber(finalRmse(B), 4)
      << ", B / A " << ratioText(finalRmse(A), finalRmse(B)) << ".</p>";
    LineChart c{"Error against time (log-log)", "seconds", "RMSE", true, true};
    for (const auto& [name, s] : {std::pair<std::string, const json*>{"A", &A}, {"B", &B}}) {
      if (!s->contains("error_vs_time")) continue;
      Line l{name + ": " + methodTitle(*s), {}};
      for (const json& e : (*s)["error_vs_time"])
        l.points.push_back({e["time_s"].get<double>(), e["rmse"].get<double>(), e["spp"].dump() + " spp"});
      if (!l.points.empty()) c.lines.push_back(l);
    }
    o << lineChart(c);
  }
  return pageSkeleton("rayes comparison: " + a.path + " and " + b.path, o.str());
}

}  // namespace rayes
