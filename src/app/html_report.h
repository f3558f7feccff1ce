// The HTML report (--report FILE.html): the stats file made readable for an artist asking
// why a frame was slow. One self-contained page (inline CSS, no scripts): where the time went,
// where the memory went, what each generation traced and diced, what the scene used and what
// was skipped, the error curve when a reference was given, and the preview image beside it.
// Built from the same JSON as --stats, so the two never disagree.
#pragma once
#include <string>
#include <nlohmann/json.hpp>

namespace rayes {

// previewImage: a path relative to the report (the PNG preview), or empty.
std::string htmlReport(const nlohmann::json& stats, const std::string& previewImage);

}  // namespace rayes
