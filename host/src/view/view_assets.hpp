#pragma once
// The files a view's page is made of, built into libnoether (view_assets.cpp): the page
// (viewer/page.html), its script (viewer/viewer.js) and three.js with its OrbitControls from
// Debian's libjs-three. Internal to libnoether.
#include <string>

namespace noether::view_assets {

// Whether three.js was found when noether was built.
bool available();
// The page with `run_json` as its NOETHER_RUN (already safe inside a <script> element).
std::string page(const std::string& run_json);

}  // namespace noether::view_assets
