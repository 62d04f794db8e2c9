#include "reporting/report_document.h"

#include <cstdint>

#include "io/input_file.h"

namespace accelcal {
namespace {

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// A Markdown table cell: a '|' in the text (|a_max|) would end the cell.
std::string EscapeCell(const std::string& cell) {
  std::string out;
  for (char c : cell) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

// A figure the plot script wrote, read whole (a short read or a memory failure is "absent",
// never a truncated image).
bool ReadFile(const std::string& path, std::string* bytes) {
  constexpr uint64_t kMaxFigureBytes = 256ull << 20;
  return ReadInputFile(path, kMaxFigureBytes, "a figure", bytes).ok();
}

// A cell of words, not a number: left-aligned, and a long one kept wide enough to read (the
// table then scrolls inside its wrapper instead of squeezing the sentence into a column one
// word wide on a phone).
constexpr size_t kLongCell = 40;  // characters

bool IsNumber(const std::string& cell) {
  return !cell.empty() && cell.find_first_not_of("0123456789+-.eE %") == std::string::npos;
}

std::string CellClass(const std::string& cell) {
  if (IsNumber(cell)) return "";
  return cell.size() > kLongCell ? " class=\"words long\"" : " class=\"words\"";
}

// A table with sentences in it: on a phone each row is shown as a block of "header: value"
// lines instead (CSS table.stack), since four columns of sentences do not fit 390 px even
// scrolled. Tables of numbers keep their columns and scroll.
bool HasSentences(const std::vector<std::vector<std::string>>& table) {
  for (size_t r = 1; r < table.size(); ++r)
    for (const std::string& cell : table[r])
      if (!IsNumber(cell) && cell.size() > kLongCell) return true;
  return false;
}

}  // namespace

std::string Base64(const std::string& bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const unsigned a = static_cast<unsigned char>(bytes[i]);
    const unsigned b = i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) : 0;
    const unsigned c = i + 2 < bytes.size() ? static_cast<unsigned char>(bytes[i + 2]) : 0;
    const unsigned triple = (a << 16) | (b << 8) | c;
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[triple & 63] : '=';
  }
  return out;
}

std::string RenderMarkdown(const ReportDocument& document) {
  std::string md = "# " + document.title + "\n\n";
  if (!document.summary.empty()) {
    md += "**In short.**\n\n";
    for (const std::string& line : document.summary) md += "- " + line + "\n";
    md += "\n";
  }
  md += "**Verdict.** " + document.verdict + "\n";
  for (const ReportSection& section : document.sections) {
    md += "\n## " + section.title + "\n\n";
    for (const std::string& paragraph : section.paragraphs) md += paragraph + "\n\n";
    for (size_t r = 0; r < section.table.size(); ++r) {
      md += "|";
      for (const std::string& cell : section.table[r]) md += " " + EscapeCell(cell) + " |";
      md += "\n";
      if (r == 0) {
        md += "|";
        for (size_t c = 0; c < section.table[r].size(); ++c) md += "---|";
        md += "\n";
      }
    }
    if (!section.table.empty()) md += "\n";
    if (!section.figure.empty())
      md += "![" + section.figure_caption + "](" + section.figure + ")\n";
  }
  return md;
}

std::string RenderHtml(const ReportDocument& document, const std::string& folder) {
  // clang-format off
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
      Escape(document.title) +
      "</title>\n<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 .8em;line-height:1.45}.table-scroll{overflow-x:auto;max-width:100%}table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right;vertical-align:top;white-space:nowrap}th{background:#eee}td.words{text-align:left}td.long{white-space:normal;min-width:16em}table.stack{width:100%}table.stack td{white-space:normal;min-width:0;overflow-wrap:anywhere}.summary{background:#eef2fa;border-left:5px solid #46a;padding:.6em 1em}.summary ul{margin:.4em 0;padding-left:1.2em}.verdict{background:#eef6ee;border-left:5px solid #4a4;padding:.6em 1em}figure{margin:1em 0;max-width:100%;overflow-x:auto}img{max-width:100%;height:auto}@media (max-width:700px){figure img{max-width:none;width:720px}table.stack,table.stack tbody,table.stack tr,table.stack td{display:block}table.stack tr:first-child{display:none}table.stack tr{border:1px solid #bbb;margin:0 0 .6em}table.stack td{border:none;text-align:left;white-space:normal;min-width:0;padding:2px 8px}table.stack td::before{content:attr(data-label) \": \";font-weight:bold}}.missing{color:#a33}</style></head><body>\n<h1>" +
      // clang-format on
      Escape(document.title) + "</h1>\n";
  if (!document.summary.empty()) {
    html += "<div class=\"summary\"><b>In short.</b>\n<ul>\n";
    for (const std::string& line : document.summary) html += "<li>" + Escape(line) + "</li>\n";
    html += "</ul>\n</div>\n";
  }
  html += "<p class=\"verdict\"><b>Verdict.</b> " + Escape(document.verdict) + "</p>\n";
  for (const ReportSection& section : document.sections) {
    html += "<h2>" + Escape(section.title) + "</h2>\n";
    for (const std::string& paragraph : section.paragraphs)
      html += "<p>" + Escape(paragraph) + "</p>\n";
    if (!section.table.empty()) {
      // A wide table scrolls inside its wrapper instead of widening the page on a phone.
      const std::vector<std::string>& header = section.table[0];
      html += HasSentences(section.table)
                  ? "<div class=\"table-scroll\">\n<table class=\"stack\">\n"
                  : "<div class=\"table-scroll\">\n<table>\n";
      for (size_t r = 0; r < section.table.size(); ++r) {
        html += "<tr>";
        for (size_t c = 0; c < section.table[r].size(); ++c) {
          const std::string& cell = section.table[r][c];
          const std::string label = c < header.size() ? header[c] : "";
          html += (r == 0 ? "<th>"
                          : "<td" + CellClass(cell) + " data-label=\"" + Escape(label) + "\">") +
                  Escape(cell) + (r == 0 ? "</th>" : "</td>");
        }
        html += "</tr>\n";
      }
      html += "</table>\n</div>\n";
    }
    if (!section.figure.empty()) {
      std::string bytes;
      if (ReadFile(folder + "/" + section.figure, &bytes)) {
        // On a phone the figure keeps a legible width and scrolls sideways, like a wide
        // table; a tap opens the PNG beside the report at full size.
        html += "<figure><a href=\"" + Escape(section.figure) + "\"><img alt=\"" +
                Escape(section.figure_caption) + "\" src=\"data:image/png;base64," + Base64(bytes) +
                "\"></a><figcaption>" + Escape(section.figure_caption) + "</figcaption></figure>\n";
      } else {
        html += "<p class=\"missing\">Figure " + Escape(section.figure) + " is absent.</p>\n";
      }
    }
  }
  return html + "</body></html>\n";
}

}  // namespace accelcal
