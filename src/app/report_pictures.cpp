#include "app/report_pictures.h"
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include "app/image_io.h"
#include "app/report_format.h"
#include "core/error.h"

namespace rayes {
namespace {

static_assert(std::endian::native == std::endian::little, "the page's script reads the values as little-endian float32");

uint8_t toSrgb8(float v) {
  if (!(v > 0)) return 0;
  if (v >= 1) return 255;
  const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return static_cast<uint8_t>(std::lround(s * 255.0f));
}

// The canvas is shown at least 320 pixels wide, scaled by whole pixels (drawn pixelated).
int displayScale(int width) { return std::max(1, 320 / std::max(1, width)); }

std::string canvasTag(const CostPictures& p, const std::string& cls, const std::string& layer, const std::string& bytes,
                      const std::string& extra) {
  std::ostringstream o;
  const int s = displayScale(p.width);
  o << "<canvas class=\"picture " << cls << "\" data-layer=" << layer << " width=" << p.width << " height=" << p.height
    << " style=\"width:" << p.width * s << "px;height:" << p.height * s << "px\"" << extra << " data-values=\""
    << base64(bytes) << "\"></canvas>";
  return o.str();
}

void heatMap(std::ostringstream& o, const CostPictures& p, const std::string& layer, const std::string& title,
             const std::string& unit, const std::string& note, std::vector<float> values) {
  float hi = 0;
  for (float v : values)
    if (std::isfinite(v)) hi = std::max(hi, v);
  // lod: where no camera sample hit a surface the level means nothing: NaN, drawn grey.
  if (layer == "lod")
    for (size_t i = 0; i < values.size(); ++i)
      if (!(p.rgba[4 * i + 3] > 0)) values[i] = std::nanf("");
  std::string bytes(values.size() * sizeof(float), '\0');
  if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  o << "<figure class=heatfigure><figcaption>" << htmlEscape(title) << "</figcaption>"
    << canvasTag(p, "heatmap", layer, bytes, " data-min=0 data-max=" + shortNumber(double(hi), 9) + " data-unit=\"" + htmlEscape(unit) + "\"")
    << "<div class=legendrow><span>0</span><canvas class=legend width=160 height=10></canvas><span>"
    << htmlEscape(shortNumber(double(hi), 4) + unit) << "</span></div><div class=pixel-readout data-layer=" << layer
    << ">&nbsp;</div><div class=note>" << htmlEscape(note) << "</div></figure>";
}

}  // namespace

std::optional<CostPictures> picturesOfStats(const StatsFile& f, std::string& note) {
  namespace fs = std::filesystem;
  const nlohmann::json& s = f.stats;
  if (!s.contains("cost_layers") || !s["cost_layers"].is_object() || !s["cost_layers"].contains("image") ||
      !s["cost_layers"]["image"].is_string()) {
    note = "";
    return std::nullopt;
  }
  const fs::path named = s["cost_layers"]["image"].get<std::string>();
  const fs::path image = named.is_absolute() ? named : fs::path(f.path).parent_path() / named;
  std::error_code ec;
  if (!fs::exists(image, ec)) {
    note = "The stats name the image " + image.string() + " for their per-pixel layers, but it is not there.";
    return std::nullopt;
  }
  try {
    const ExrChannels c = readExrChannels(image.string(), {"R", "G", "B", "A", "lod.Y", "dicings.Y", "time.Y"}, "the image of the cost layers");
    if (uint64_t(c.width) * uint64_t(c.height) > kMaxPicturePixels) {
      note = image.string() + " is " + std::to_string(c.width) + "x" + std::to_string(c.height) +
             ": above the " + std::to_string(kMaxPicturePixels) + " pixels a page embeds; open its layers in an image viewer.";
      return std::nullopt;
    }
    CostPictures p;
    p.width = c.width;
    p.height = c.height;
    p.source = image.string();
    const size_t n = size_t(c.width) * size_t(c.height);
    p.rgba.assign(4 * n, 0.0f);
    for (size_t ch = 0; ch < 4; ++ch)
      if (!c.channels[ch].empty())
        for (size_t i = 0; i < n; ++i) p.rgba[4 * i + ch] = c.channels[ch][i];
    p.lod = c.channels[4];
    p.dicings = c.channels[5];
    p.seconds = c.channels[6];
    return p;
  } catch (const InputError& e) {
    note = std::string("The image of the per-pixel layers cannot be read: ") + e.what();
    return std::nullopt;
  }
}

std::string picturesSection(const CostPictures& p) {
  std::ostringstream o;
  o << "<h2>Where on the image</h2>";
  if (uint64_t(p.width) * uint64_t(p.height) > kMaxPicturePixels || p.width <= 0 || p.height <= 0) {
    o << "<p>The image is " << p.width << "&times;" << p.height << ": no pictures above " << kMaxPicturePixels << " pixels.</p>";
    return o.str();
  }
  const size_t n = size_t(p.width) * size_t(p.height);
  o << "<p>From " << htmlEscape(p.source) << ". Move the cursor over a picture: every read-out shows its layer's value "
    << "at that pixel (x from the left, y from the top of the image's window).</p><div class=pictures>";
  std::string rgb(3 * n, '\0');
  for (size_t i = 0; i < n; ++i)
    for (size_t c = 0; c < 3; ++c) rgb[3 * i + c] = char(toSrgb8(p.rgba[4 * i + c]));
  o << "<figure class=heatfigure><figcaption>Beauty (clamped to 1, sRGB)</figcaption>" << canvasTag(p, "beauty", "beauty", rgb, "")
    << "<div class=pixel-readout data-layer=beauty>&nbsp;</div></figure>";
  if (p.lod.size() == n)
    heatMap(o, p, "lod", "Level of detail at the first hit (lod.Y)", "",
            "Mean level over the pixel's samples that hit (a grid of 4^m micro-quads); grey: no surface.", p.lod);
  if (p.dicings.size() == n)
    heatMap(o, p, "dicings", "Dicings charged to the pixel (dicings.Y)", "",
            "Each dicing shared equally among the rays that caused it, summed over the pixel's camera paths.", p.dicings);
  if (p.seconds.size() == n)
    heatMap(o, p, "time", "Time per pixel (time.Y)", " s",
            "Each batch's wall time shared among its paths by the rays they traced: a measurement, not repeatable.", p.seconds);
  o << "</div>";
  return o.str();
}

}  // namespace rayes
