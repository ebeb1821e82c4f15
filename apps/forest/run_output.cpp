#include "run_output.hpp"

#include <fmt/format.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "forest/core/drawing.hpp"
#include "forest/core/log.hpp"

namespace forest::app {

namespace fs = std::filesystem;

int clearEarlierRun(const fs::path& folder, const std::vector<std::string>& ownedFiles, bool framesFolder) {
  int removed = 0;
  for (const std::string& name : ownedFiles) removed += fs::remove(folder / name) ? 1 : 0;
  const fs::path frames = folder / "frames";
  if (framesFolder && fs::is_directory(frames)) {
    for (const fs::directory_entry& entry : fs::directory_iterator(frames)) {
      const std::string name = entry.path().filename().string();
      if (entry.is_regular_file() && name.starts_with("frame") && entry.path().extension() == ".png") {
        fs::remove(entry.path());
        ++removed;
      }
    }
  }
  return removed;
}

int clearEarlierWalk(const fs::path& folder) {
  const int removed = clearEarlierRun(folder, {"report.json", "contact-sheet.png", "walkthrough.mp4", "window.png"}, true);
  if (removed > 0) log::info("removed {} files of an earlier run from {}", removed, folder.string());
  return removed;
}

ContactSheet::ContactSheet(int maxThumbnails, int thumbnailWidth) : max_(maxThumbnails), width_(thumbnailWidth) {}

bool ContactSheet::has(int frame) const {
  return std::any_of(kept_.begin(), kept_.end(), [frame](const Thumbnail& t) { return t.frame == frame; });
}

namespace {

// The image shrunk by an integer factor with a box filter: cheap enough to run on a tenth of a
// walk's frames (a filtered resize of a 1280×720 frame costs ~0.3 s on this machine).
Image8 boxShrunk(const Image8& image, int factor) {
  if (factor <= 1) return image;
  Image8 out(image.width / factor, image.height / factor, image.channels);
  const int area = factor * factor;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < image.channels; ++c) {
        int sum = 0;
        for (int dy = 0; dy < factor; ++dy)
          for (int dx = 0; dx < factor; ++dx) sum += image.at(x * factor + dx, y * factor + dy, c);
        out.at(x, y, c) = static_cast<unsigned char>(sum / area);
      }
  return out;
}

}  // namespace

void ContactSheet::add(int frame, double timeSeconds, double frameMs, const Image8& image) {
  const int factor = (image.width + width_ - 1) / width_;  // the smallest that fits the width cap
  std::erase_if(kept_, [frame](const Thumbnail& t) { return t.frame == frame; });
  kept_.push_back({frame, timeSeconds, frameMs, boxShrunk(image, factor)});
  std::sort(kept_.begin(), kept_.end(), [](const Thumbnail& a, const Thumbnail& b) { return a.frame < b.frame; });
  if (static_cast<int>(kept_.size()) > 2 * max_) {
    const int last = kept_.back().frame;  // the newest stays: it may be the run's last frame
    stride_ *= 2;
    std::erase_if(kept_, [&](const Thumbnail& t) { return t.frame % stride_ != 0 && t.frame != last; });
  }
}

// Up to max_ of the kept frames, evenly spread over them, the first and the last always in.
std::vector<size_t> ContactSheet::shownIndices() const {
  std::vector<size_t> shown;
  const size_t count = std::min(kept_.size(), static_cast<size_t>(max_));
  for (size_t i = 0; i < count; ++i) {
    const double last = static_cast<double>(kept_.size() - 1), steps = static_cast<double>(count - 1);
    shown.push_back(count == 1 ? 0 : static_cast<size_t>(std::lround(static_cast<double>(i) * last / steps)));
  }
  return shown;
}

std::vector<int> ContactSheet::shownFrames() const {
  std::vector<int> frames;
  for (size_t k : shownIndices()) frames.push_back(kept_[k].frame);
  return frames;
}

Image8 ContactSheet::compose() const {
  if (kept_.empty()) return Image8(1, 1, 4);
  std::vector<const Thumbnail*> shown;
  for (size_t k : shownIndices()) shown.push_back(&kept_[k]);
  const int columns = static_cast<int>(std::min<size_t>(4, shown.size()));
  const int rows = static_cast<int>((shown.size() + columns - 1) / columns);
  const int w = shown.front()->image.width, h = shown.front()->image.height, gap = 2;
  Image8 sheet(columns * w + (columns - 1) * gap, rows * h + (rows - 1) * gap, 4);
  std::fill(sheet.pixels.begin(), sheet.pixels.end(), static_cast<unsigned char>(255));
  const int band = std::min(18, h / 3);
  for (size_t i = 0; i < shown.size(); ++i) {
    const glm::ivec2 at(static_cast<int>(i % columns) * (w + gap), static_cast<int>(i / columns) * (h + gap));
    paste(sheet, shown[i]->image, at);
    // The label on a dark band at the thumbnail's bottom: frame, path time, frame time.
    const std::vector<glm::dvec2> bandPolygon{{at.x, at.y + h - band}, {at.x + w, at.y + h - band}, {at.x + w, at.y + h}, {at.x, at.y + h}};
    fillConvexPolygon(sheet, bandPolygon, glm::vec3(0.0f), 0.65f);
    drawText(sheet, {at.x + 4, at.y + h - band / 4 - 1},
             fmt::format("frame {}  t {:.1f} s  {:.0f} ms", shown[i]->frame, shown[i]->time, shown[i]->frameMs), glm::vec3(1.0f),
             std::max(8, band - 6));
  }
  return sheet;
}

std::string shellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

VideoWriter::VideoWriter(const std::filesystem::path& file, int width, int height, double fps) : width_(width), height_(height) {
  if (std::system("command -v ffmpeg > /dev/null 2>&1") != 0) {
    why_ = "ffmpeg is not installed (tools/setup.sh installs it)";
    return;
  }
  command_ = fmt::format(
      "nice -n 19 ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgba -s {}x{} -framerate {} -i - -threads 1 "
      "-vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -preset veryfast -pix_fmt yuv420p {}",
      width, height, fps, shellQuoted(file.string()));
  pipe_ = popen(command_.c_str(), "w");
  if (!pipe_) why_ = "ffmpeg could not be started";
}

VideoWriter::~VideoWriter() {
  if (pipe_) pclose(pipe_);
}

void VideoWriter::add(const Image8& image) {
  if (!pipe_) return;
  if (image.width != width_ || image.height != height_ || image.channels != 4) {
    why_ = fmt::format("a {}x{} frame of {} channels in a {}x{} RGBA video", image.width, image.height, image.channels, width_, height_);
  } else if (std::fwrite(image.pixels.data(), 1, image.pixels.size(), pipe_) == image.pixels.size()) {
    ++frames_;
    return;
  } else {
    why_ = "ffmpeg stopped reading frames";
  }
  pclose(pipe_);
  pipe_ = nullptr;
}

bool VideoWriter::finish() {
  if (!pipe_) return false;
  const int status = pclose(pipe_);
  pipe_ = nullptr;
  if (status == 0) return true;
  why_ = fmt::format("ffmpeg exited with {}", WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  log::warn("video: {}: {}", why_, command_);
  return false;
}

}  // namespace forest::app
