// The view's page, script and three.js, built in with the assembler's .incbin (the files are
// read when this file is compiled: host/CMakeLists.txt names them as its dependencies), so that
// `noether view` needs no file at run time and its pages no network.
#include "view/view_assets.hpp"

#include <noether/error.hpp>

#include <string_view>

// NAME_begin … NAME_end: the bytes of FILE, local to libnoether.
#define NOETHER_EMBED(name, file)                                                   \
  asm(".pushsection .rodata\n"                                                      \
      ".hidden " #name "_begin\n.hidden " #name "_end\n"                            \
      ".globl " #name "_begin\n.globl " #name "_end\n"                              \
      #name "_begin:\n.incbin \"" file "\"\n" #name "_end:\n.byte 0\n.popsection\n"); \
  extern "C" const char name##_begin[], name##_end[];

#ifdef NOETHER_THREE_JS
NOETHER_EMBED(noether_view_page, NOETHER_VIEWER_DIR "/page.html")
NOETHER_EMBED(noether_view_script, NOETHER_VIEWER_DIR "/viewer.js")
NOETHER_EMBED(noether_view_three, NOETHER_THREE_JS)
NOETHER_EMBED(noether_view_controls, NOETHER_ORBIT_CONTROLS_JS)
#endif

namespace noether::view_assets {

#ifdef NOETHER_THREE_JS
bool available() { return true; }

std::string page(const std::string& run_json) {
  std::string html(noether_view_page_begin, noether_view_page_end);
  // The markers in the order they appear, each looked for after what the one before put in: a
  // marker's text inside three.js is never taken for one.
  std::size_t from = 0;
  const auto put = [&html, &from](std::string_view marker, std::string_view text) {
    const auto at = html.find(marker, from);
    if (at == std::string::npos) throw Error("the view's page has no " + std::string(marker));
    html.replace(at, marker.size(), text);
    from = at + text.size();
  };
  put("/*@three@*/", std::string_view(noether_view_three_begin, static_cast<std::size_t>(noether_view_three_end - noether_view_three_begin)));
  put("/*@controls@*/", std::string_view(noether_view_controls_begin, static_cast<std::size_t>(noether_view_controls_end - noether_view_controls_begin)));
  put("/*@run@*/", run_json);
  put("/*@viewer@*/", std::string_view(noether_view_script_begin, static_cast<std::size_t>(noether_view_script_end - noether_view_script_begin)));
  return html;
}
#else
bool available() { return false; }
std::string page(const std::string&) { throw Error("this noether was built without three.js"); }
#endif

}  // namespace noether::view_assets
