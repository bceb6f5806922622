// A screen's content drawn into an image with OpenCV: the title, the wrapped text and the options as buttons, at
// the largest font that fits.
#include "screen_renderer.h"

#include <algorithm>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace quiver::agents::devices::internal {
namespace {

const cv::Scalar kBackground(250, 247, 243);  // BGR
const cv::Scalar kTitleColour(90, 50, 20);
const cv::Scalar kTextColour(40, 40, 40);
const cv::Scalar kButtonColour(225, 205, 180);
const cv::Scalar kButtonTextColour(60, 30, 10);
const cv::Scalar kHighlightColour(40, 140, 230);
const cv::Scalar kHighlightTextColour(255, 255, 255);

constexpr int kTitleFont = cv::FONT_HERSHEY_DUPLEX;
constexpr int kBodyFont = cv::FONT_HERSHEY_SIMPLEX;

struct Font {
  int face;
  double scale;
  int thickness;

  int line_height() const {
    int baseline = 0;
    cv::Size s = cv::getTextSize("Ag", face, scale, thickness, &baseline);
    return s.height + baseline + std::max(2, s.height / 3);
  }
  int width(const std::string& s) const {
    int baseline = 0;
    return cv::getTextSize(s, face, scale, thickness, &baseline).width;
  }
};

// Splits a too-long word into pieces no wider than `max_width` (at least one character each).
void break_word(const std::string& word, const Font& f, int max_width,
                std::vector<std::string>& lines) {
  std::string piece;
  for (char c : word) {
    if (!piece.empty() && f.width(piece + c) > max_width) {
      lines.push_back(piece);
      piece.clear();
    }
    piece += c;
  }
  if (!piece.empty()) lines.push_back(piece);
}

// Greedy word wrap of ASCII `text` into lines no wider than `max_width`; '\n' starts a new line.
std::vector<std::string> wrap(const std::string& text, const Font& f, int max_width) {
  std::vector<std::string> lines;
  std::size_t para_start = 0;
  while (para_start <= text.size()) {
    std::size_t para_end = text.find('\n', para_start);
    if (para_end == std::string::npos) para_end = text.size();
    std::string line;
    std::size_t i = para_start;
    while (i < para_end) {
      while (i < para_end && text[i] == ' ') ++i;
      std::size_t j = i;
      while (j < para_end && text[j] != ' ') ++j;
      if (j == i) break;
      std::string word = text.substr(i, j - i);
      i = j;
      std::string candidate = line.empty() ? word : line + ' ' + word;
      if (f.width(candidate) <= max_width) {
        line = std::move(candidate);
        continue;
      }
      if (!line.empty()) lines.push_back(std::move(line));
      line.clear();
      if (f.width(word) <= max_width) {
        line = std::move(word);
      } else {
        break_word(word, f, max_width, lines);
        line = std::move(lines.back());
        lines.pop_back();
      }
    }
    if (!line.empty()) lines.push_back(std::move(line));
    para_start = para_end + 1;
  }
  return lines;
}

// `utf8` for drawing with its line breaks kept ('\n' never occurs inside a UTF-8 sequence).
std::string drawable(std::string_view utf8) {
  std::string out;
  std::size_t start = 0;
  for (;;) {
    std::size_t nl = utf8.find('\n', start);
    out += to_hershey_text(utf8.substr(start, nl == std::string_view::npos ? nl : nl - start));
    if (nl == std::string_view::npos) return out;
    out += '\n';
    start = nl + 1;
  }
}

void fill_rounded_rect(cv::Mat& img, const cv::Rect& r, int radius, const cv::Scalar& colour) {
  radius = std::max(0, std::min({radius, r.width / 2, r.height / 2}));
  cv::rectangle(img, cv::Rect(r.x + radius, r.y, r.width - 2 * radius, r.height), colour,
                cv::FILLED, cv::LINE_AA);
  cv::rectangle(img, cv::Rect(r.x, r.y + radius, r.width, r.height - 2 * radius), colour,
                cv::FILLED, cv::LINE_AA);
  const cv::Point corners[4] = {{r.x + radius, r.y + radius},
                                {r.x + r.width - 1 - radius, r.y + radius},
                                {r.x + radius, r.y + r.height - 1 - radius},
                                {r.x + r.width - 1 - radius, r.y + r.height - 1 - radius}};
  for (const cv::Point& c : corners) cv::circle(img, c, radius, colour, cv::FILLED, cv::LINE_AA);
}

// Draws `lines` from top `y` (the top of the first line), left-aligned at `x` or centred in
// [x, x + width) when `centred`. Returns the y below the last line.
int draw_lines(cv::Mat& img, const std::vector<std::string>& lines, const Font& f, int x, int y,
               int width, bool centred, const cv::Scalar& colour) {
  const int lh = f.line_height();
  int baseline = 0;
  const int ascent = cv::getTextSize("Ag", f.face, f.scale, f.thickness, &baseline).height;
  for (const std::string& line : lines) {
    int lx = centred ? x + (width - f.width(line)) / 2 : x;
    cv::putText(img, line, cv::Point(lx, y + ascent), f.face, f.scale, colour, f.thickness,
                cv::LINE_AA);
    y += lh;
  }
  return y;
}

struct Layout {
  Font title_font, body_font, button_font;
  std::vector<std::string> title, text;
  std::vector<std::vector<std::string>> labels;
  bool one_row = false;
  int button_padding = 0;
  int gap = 0;
  int height = 0;  // total height needed
};

Layout lay_out(const std::string& title, const std::string& text,
               const std::vector<std::string>& options, int width, int margin, double scale) {
  Layout l;
  const int thick = std::max(1, static_cast<int>(scale * 2 + 0.5));
  l.title_font = {kTitleFont, 1.1 * scale, thick};
  l.body_font = {kBodyFont, 0.85 * scale, std::max(1, thick - 1)};
  l.button_font = {kBodyFont, 0.8 * scale, std::max(1, thick - 1)};
  l.gap = std::max(4, static_cast<int>(14 * scale));
  l.button_padding = std::max(4, static_cast<int>(12 * scale));
  const int inner = width - 2 * margin;
  l.title = wrap(title, l.title_font, inner);
  l.text = wrap(text, l.body_font, inner);

  int h = margin;
  if (!l.title.empty()) h += static_cast<int>(l.title.size()) * l.title_font.line_height() + l.gap;
  if (!l.text.empty()) h += static_cast<int>(l.text.size()) * l.body_font.line_height() + l.gap;

  const int n = static_cast<int>(options.size());
  if (n > 0) {
    // One row when every label fits on one line of an equal-width column.
    const int column = (inner - (n - 1) * l.gap) / n - 2 * l.button_padding;
    l.one_row = column > 0;
    for (const std::string& o : options) {
      if (!l.one_row || l.button_font.width(o) > column) l.one_row = false;
    }
    const int label_width = l.one_row ? column : inner - 2 * l.button_padding;
    int buttons = 0;
    for (const std::string& o : options) {
      l.labels.push_back(wrap(o, l.button_font, std::max(1, label_width)));
      const int bh = static_cast<int>(l.labels.back().size()) * l.button_font.line_height() +
                     2 * l.button_padding;
      buttons = l.one_row ? std::max(buttons, bh) : buttons + bh + l.gap;
    }
    if (!l.one_row) buttons -= l.gap;
    h += buttons;
  }
  l.height = h + margin;
  return l;
}

}  // namespace

cv::Mat render_blank_screen(int width, int height) {
  return cv::Mat(height, width, CV_8UC3, kBackground);
}

cv::Mat render_screen(const ScreenContent& c, int width, int height) {
  cv::Mat img = render_blank_screen(width, height);
  const int margin = std::max(6, std::min(width, height) / 30);
  const std::string title = drawable(c.title);
  const std::string text = drawable(c.text);
  std::vector<std::string> options;
  for (const std::string& o : c.options) options.push_back(drawable(o));

  // The largest font (relative to an 800x480 screen) at which everything fits.
  const double base = std::min(width / 800.0, height / 480.0);
  double scale = 1.0;
  Layout l = lay_out(title, text, options, width, margin, base * scale);
  while (l.height > height && scale > 0.3) {
    scale *= 0.9;
    l = lay_out(title, text, options, width, margin, base * scale);
  }

  const int inner = width - 2 * margin;
  int y = margin;
  if (!l.title.empty()) {
    y = draw_lines(img, l.title, l.title_font, margin, y, inner, false, kTitleColour) + l.gap;
  }
  if (!l.text.empty()) {
    y = draw_lines(img, l.text, l.body_font, margin, y, inner, false, kTextColour) + l.gap;
  }
  const int n = static_cast<int>(l.labels.size());
  if (n == 0) return img;
  // Buttons sit at the bottom of the screen when there is room, else right below the text.
  const int lh = l.button_font.line_height();
  std::vector<int> heights;
  int total = 0;
  for (const auto& lines : l.labels) {
    heights.push_back(static_cast<int>(lines.size()) * lh + 2 * l.button_padding);
  }
  if (l.one_row) {
    total = *std::max_element(heights.begin(), heights.end());
    std::fill(heights.begin(), heights.end(), total);
  } else {
    for (int h : heights) total += h;
    total += (n - 1) * l.gap;
  }
  y = std::max(y, height - margin - total);
  const int column = l.one_row ? (inner - (n - 1) * l.gap) / n : inner;
  int x = margin;
  for (int i = 0; i < n; ++i) {
    const bool lit = i == c.highlighted;
    cv::Rect r(x, y, column, heights[i]);
    fill_rounded_rect(img, r, std::max(4, heights[i] / 4), lit ? kHighlightColour : kButtonColour);
    const int text_h = static_cast<int>(l.labels[i].size()) * lh;
    draw_lines(img, l.labels[i], l.button_font, x + l.button_padding, y + (heights[i] - text_h) / 2,
               column - 2 * l.button_padding, true, lit ? kHighlightTextColour : kButtonTextColour);
    if (l.one_row) {
      x += column + l.gap;
    } else {
      y += heights[i] + l.gap;
    }
  }
  return img;
}

}  // namespace quiver::agents::devices::internal
