#include "io/json_file.h"

#include <cmath>
#include <new>
#include <set>
#include <string_view>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_text.h"

namespace accelcal {
namespace {

std::string FindNonFinite(const nlohmann::json& json, const std::string& pointer) {
  if (json.is_number_float()) {
    return std::isfinite(json.get<double>()) ? "" : (pointer.empty() ? "/" : pointer);
  }
  if (json.is_object()) {
    for (auto it = json.begin(); it != json.end(); ++it) {
      const std::string found = FindNonFinite(it.value(), pointer + "/" + it.key());
      if (!found.empty()) return found;
    }
  } else if (json.is_array()) {
    for (size_t i = 0; i < json.size(); ++i) {
      const std::string found = FindNonFinite(json[i], pointer + "/" + std::to_string(i));
      if (!found.empty()) return found;
    }
  }
  return "";
}

// A reference token of a JSON pointer (RFC 6901: '~' is written "~0", '/' "~1"), cut for
// a message.
std::string PointerToken(const std::string& token) {
  std::string escaped;
  for (const char c : token) {
    if (c == '~') {
      escaped += "~0";
    } else if (c == '/') {
      escaped += "~1";
    } else {
      escaped.push_back(c);
    }
  }
  return EchoInput(escaped);
}

// nlohmann's parse error, with the text it quotes cut for a message: the lexer's token after
// "last read: '", which for an unterminated string is everything up to the end of the file.
// The rest of the message quotes nothing of the input.
std::string ParseErrorText(const std::string& what) {
  const std::string marker = "last read: '";
  const size_t at = what.find(marker);
  if (at == std::string::npos) {
    // Other errors quote the text too ("number overflow parsing '1000...'"): cap any quote.
    const size_t open = what.find('\'');
    const size_t close = open == std::string::npos ? open : what.rfind('\'');
    if (open == std::string::npos || close <= open) return EchoInput(what);
    return what.substr(0, open + 1) +
           EchoInput(std::string_view(what).substr(open + 1, close - open - 1)) +
           what.substr(close);
  }
  const size_t begin = at + marker.size();
  size_t end = what.rfind("'; expected ");
  if (end == std::string::npos || end < begin) end = what.size() - 1;
  if (end < begin || what[end] != '\'') return EchoInput(what);
  return what.substr(0, begin) + EchoInput(std::string_view(what).substr(begin, end - begin)) +
         what.substr(end);
}

// Where the parser is: one frame per object or array being read.
struct Frame {
  bool array = false;
  std::set<std::string> keys;  // an object's keys so far
  std::string key;             // an object's current key
  size_t index = 0;            // an array's current element
};

// Thrown by the parser's callback to stop at a level deeper than kMaxJsonDepth, before the
// document holds it.
struct TooDeep {};

}  // namespace

Status ParseJsonStrict(const std::string& text, nlohmann::json* document) {
  using nlohmann::json;
  std::vector<Frame> frames;
  std::string duplicate_key;
  std::string duplicate_pointer;
  std::string deep_pointer;
  const json::parser_callback_t callback = [&](int /*depth*/, json::parse_event_t event,
                                               json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (frames.size() >= static_cast<size_t>(kMaxJsonDepth)) {
          // Where it happens, by the outermost key or element: the rest is a long "/0/0/0...".
          const Frame& outer = frames.front();
          deep_pointer =
              "/" + (outer.array ? std::to_string(outer.index) : PointerToken(outer.key));
          throw TooDeep();
        }
        frames.emplace_back();
        frames.back().array = event == json::parse_event_t::array_start;
        break;
      case json::parse_event_t::key: {
        Frame& frame = frames.back();
        frame.key = parsed.get<std::string>();
        if (!frame.keys.insert(frame.key).second && duplicate_key.empty()) {
          duplicate_key = frame.key;
          for (const Frame& outer : frames) {
            duplicate_pointer +=
                "/" + (outer.array ? std::to_string(outer.index) : PointerToken(outer.key));
          }
        }
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        frames.pop_back();
        if (!frames.empty() && frames.back().array) ++frames.back().index;
        break;
      case json::parse_event_t::value:
        if (!frames.empty() && frames.back().array) ++frames.back().index;
        break;
    }
    return true;
  };
  *document = json();
  try {
    *document = json::parse(text, callback);
  } catch (const json::exception& error) {
    *document = json();
    return Status::Error("not valid JSON (" + ParseErrorText(error.what()) + ")");
  } catch (const TooDeep&) {
    *document = json();
    return Status::Error("arrays and objects nested more than " + std::to_string(kMaxJsonDepth) +
                         " deep, under " + deep_pointer +
                         "; no accelcal input nests beyond a few levels: the file is damaged or "
                         "not the one meant");
  } catch (const std::bad_alloc&) {
    *document = json();
    return Status::Error(
        "not enough memory to parse the JSON text; free memory or raise the "
        "limit (ulimit -v)");
  }
  if (!duplicate_key.empty()) {
    *document = json();
    return Status::Error("key \"" + EchoInput(duplicate_key) +
                         "\" is given twice in one object, at " + duplicate_pointer +
                         "; a JSON reader would keep only one of the two values: remove the "
                         "other");
  }
  return Status::Ok();
}

std::string FirstNonFiniteNumber(const nlohmann::json& json) { return FindNonFinite(json, ""); }

Status JsonText(const nlohmann::json& json, std::string* text) {
  const std::string where = FirstNonFiniteNumber(json);
  if (!where.empty()) {
    return Status::Error("the result holds a non-finite number at " + where +
                         ", so nothing was written; this is a bug, please report it with the "
                         "command line and data");
  }
  // Every string was checked where it was read; should one still not be UTF-8, it is
  // written with U+FFFD rather than failing the whole run.
  *text = json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  return Status::Ok();
}

Status WriteJsonAtomically(const std::string& path, const nlohmann::json& json) {
  std::string text;
  ACCELCAL_RETURN_IF_ERROR(JsonText(json, &text));
  return WriteFileAtomically(path, text);
}

}  // namespace accelcal
