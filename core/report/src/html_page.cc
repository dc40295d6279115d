// HtmlPage (html_page.h): one self-contained document, style and the render check inline.
#include "cellmetry/report/html_page.h"

#include <algorithm>

#include "cellmetry/report/svg_plot.h"

namespace cellmetry::report {
namespace {

// Layout: the body is at most 1250 px wide plus padding (fits a 1,400 px window); a table sits
// in a container that scrolls sideways (.table-scroll) so a wide one never widens the page, and
// long cells (.wrap) and long words in text wrap; a plot wider than the page is scaled down.
constexpr const char* kStyle = R"(
body{font:14px/1.45 system-ui,-apple-system,"Segoe UI",sans-serif;margin:0 auto;max-width:1250px;
padding:16px 24px;color:#222;overflow-wrap:anywhere}
h1{font-size:22px;margin:4px 0}
h2{font-size:17px;margin:26px 0 6px;border-bottom:1px solid #ddd;padding-bottom:3px}
.sub{color:#555}.note{color:#666;font-size:12.5px}nav a{margin-right:12px;font-size:13px}
.table-scroll{overflow-x:auto;max-width:100%;margin:6px 0}
table{border-collapse:collapse;font-size:12.5px}
td,th{border:1px solid #ddd;padding:2px 7px;text-align:right;white-space:nowrap}
th{background:#f3f3f3}td:first-child,th:first-child{text-align:left}
td.wrap,th.wrap{white-space:normal;text-align:left;min-width:14em;max-width:36em}
.grid{display:flex;flex-wrap:wrap;gap:8px 18px}figure{margin:4px 0;max-width:100%}
figcaption{font-size:12px;color:#555;max-width:380px}
svg{max-width:100%;height:auto}
svg text{font-size:10.5px;fill:#333}svg .label{font-size:11.5px}svg .frame{fill:#fff;stroke:#999}
svg .ticks line{stroke:#999}svg line.grid{stroke:#eee}svg line.zero{stroke:#888;stroke-width:.8}
)";

// Runs once the page has loaded; the page reads the same without it (see html_page.h).
constexpr const char* kCheck = R"(
window.addEventListener('load',function(){
var h=document.documentElement,f=document.querySelectorAll('figure.plot'),d=0,o=0;
function cross(a,b){
return a.left<b.right-.5&&b.left<a.right-.5&&a.top<b.bottom-.5&&b.top<a.bottom-.5;}
for(var i=0;i<f.length;i++){var s=f[i].querySelector('svg'),b=s?s.getBoundingClientRect():null;
var ok=b&&b.width>0&&b.height>0&&s.querySelectorAll('.marks > *').length>0;
f[i].setAttribute('data-drawn',ok?'1':'0');if(ok)d++;
var l=s?s.querySelector('[data-role=legend]'):null;
var a=s?s.querySelector('[data-role=plot-area]'):null;
if(l&&a&&cross(l.getBoundingClientRect(),a.getBoundingClientRect())){
o++;f[i].setAttribute('data-legend-overlap','1');}}
var t=document.querySelectorAll('.table-scroll'),w=0;
for(var k=0;k<t.length;k++)if(t[k].scrollWidth>t[k].clientWidth+1)w++;
h.setAttribute('data-plots',String(f.length));h.setAttribute('data-plots-drawn',String(d));
h.setAttribute('data-legend-overlaps',String(o));
h.setAttribute('data-page-width',String(Math.max(h.scrollWidth,document.body.scrollWidth)));
h.setAttribute('data-window-width',String(window.innerWidth));
h.setAttribute('data-tables-scrolling',String(w));
h.setAttribute('data-report-ready','1');});
)";

// Table cells longer than this wrap (class "wrap") instead of stretching their column.
constexpr size_t kLongCell = 48;

std::string Cell(const char* tag, const std::string& text) {
  const std::string open = text.size() > kLongCell ? std::string("<") + tag + " class=\"wrap\">"
                                                   : std::string("<") + tag + ">";
  return open + EscapeXml(text) + "</" + tag + ">";
}

}  // namespace

HtmlPage::HtmlPage(std::string title, std::string subtitle)
    : title_(std::move(title)), subtitle_(std::move(subtitle)) {}

void HtmlPage::Section(const std::string& heading, const std::string& id) {
  const std::string anchor = id.empty() ? "s" + std::to_string(toc_.size()) : id;
  body_ += "<h2 id=\"" + EscapeXml(anchor) + "\">" + EscapeXml(heading) + "</h2>\n";
  toc_ += "<a href=\"#" + EscapeXml(anchor) + "\">" + EscapeXml(heading) + "</a>";
}

void HtmlPage::Paragraph(const std::string& text) { body_ += "<p>" + EscapeXml(text) + "</p>\n"; }
void HtmlPage::Note(const std::string& text) {
  body_ += "<p class=\"note\">" + EscapeXml(text) + "</p>\n";
}
void HtmlPage::Raw(const std::string& markup) { body_ += markup + "\n"; }
void HtmlPage::BeginGrid() { body_ += "<div class=\"grid\">\n"; }
void HtmlPage::EndGrid() { body_ += "</div>\n"; }

void HtmlPage::Table(const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows, int max_rows) {
  body_ += "<div class=\"table-scroll\"><table><tr>";
  for (const auto& h : header) body_ += Cell("th", h);
  body_ += "</tr>\n";
  const size_t shown =
      max_rows > 0 ? std::min(rows.size(), static_cast<size_t>(max_rows)) : rows.size();
  for (size_t r = 0; r < shown; ++r) {
    body_ += "<tr>";
    for (const auto& cell : rows[r]) body_ += Cell("td", cell);
    body_ += "</tr>\n";
  }
  body_ += "</table></div>\n";
  if (shown < rows.size()) {
    Note("first " + std::to_string(shown) + " of " + std::to_string(rows.size()) +
         " rows; the result folder's CSV holds them all");
  }
}

std::string HtmlPage::Html() const {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" +
         EscapeXml(title_) + "</title><style>" + kStyle + "</style></head><body>\n<h1>" +
         EscapeXml(title_) + "</h1>\n" +
         (subtitle_.empty() ? "" : "<p class=\"sub\">" + EscapeXml(subtitle_) + "</p>\n") +
         "<nav>" + toc_ + "</nav>\n" + body_ + "<script>" + kCheck + "</script>\n</body></html>\n";
}

}  // namespace cellmetry::report
