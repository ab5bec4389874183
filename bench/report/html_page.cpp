#include "bench/report/html_page.h"

#include "bench/report/svg_charts.h"

namespace penumbra::bench {

std::string htmlPage(const std::string& title, const std::string& body,
                     const nlohmann::json& numbers) {
  return "<!DOCTYPE html>\n<html><head><meta charset='utf-8'/><title>" + escapeHtml(title) +
         "</title>\n"
         "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
         "table{border-collapse:collapse;font-size:12px;margin:1em 0}td,th{border:1px solid #ccc;"
         "padding:2px 6px;text-align:right}figure{margin:1em 0}pre{background:#f6f6f6;padding:1em;"
         "overflow:auto;max-height:30em;font-size:11px}</style></head><body>\n<h1>" +
         escapeHtml(title) + "</h1>\n" + body + "<h2>Numbers (JSON)</h2>\n<pre>" +
         escapeHtml(numbers.dump(1)) + "</pre>\n</body></html>\n";
}

}  // namespace penumbra::bench
