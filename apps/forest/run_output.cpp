#include "run_output.hpp"

#include <fmt/format.h>

#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <thread>

#include "forest/core/drawing.hpp"
#include "forest/core/error.hpp"
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

std::string benchmarkStamp(const std::string& device) {
  std::string cpu = "an unknown CPU";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  const std::time_t now = std::time(nullptr);
  char date[16];
  std::strftime(date, sizeof date, "%Y-%m-%d", std::localtime(&now));
  return fmt::format("Measured {} on {} cores of {}; GL: {}.", date, std::thread::hardware_concurrency(), cpu, device);
}

std::string shellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

VideoWriter::VideoWriter(const std::filesystem::path& file, int width, int height, double fps) : width_(width), height_(height) {
  const std::vector<std::string> arguments{"ffmpeg", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba", "-s",
                                           fmt::format("{}x{}", width, height), "-framerate", fmt::format("{}", fps), "-i", "-",
                                           "-threads", "1", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-preset",
                                           "veryfast", "-pix_fmt", "yuv420p", file.string()};
  // A socket rather than a pipe: a write to a reader that died fails (MSG_NOSIGNAL) instead of
  // killing this process with SIGPIPE.
  int ends[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends) != 0) {
    why_ = systemErrorMessage("video: socketpair");
    return;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, ends[1], STDIN_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setpgroup(&attributes, 0);  // its own group: Ctrl-C stops the run, which then finishes the video
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  std::vector<char*> argv;
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const int error = posix_spawnp(&pid_, "ffmpeg", &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  close(ends[1]);
  if (error != 0) {
    close(ends[0]);
    pid_ = -1;
    why_ = error == ENOENT ? std::string("ffmpeg is not installed (tools/setup.sh installs it)")
                           : fmt::format("ffmpeg could not be started: {}", std::strerror(error));
    return;
  }
  socket_ = ends[0];
  kill(pid_, SIGSTOP);  // it runs only while it is given a frame (add)
}

VideoWriter::~VideoWriter() { stop(); }

void VideoWriter::stop() {
  if (socket_ >= 0) close(socket_);
  socket_ = -1;
  if (pid_ > 0) {
    kill(pid_, SIGCONT);
    int status = 0;
    waitpid(pid_, &status, 0);
    status_ = status;
  }
  pid_ = -1;
}

void VideoWriter::add(const Image8& image) {
  if (!ok()) return;
  if (image.width != width_ || image.height != height_ || image.channels != 4) {
    why_ = fmt::format("a {}x{} frame of {} channels in a {}x{} RGBA video", image.width, image.height, image.channels, width_, height_);
    stop();
    return;
  }
  // ffmpeg encodes the frame before this one while it takes this one, then stops again: it never
  // runs while the next frame renders (a concurrent encoder skews what the frame measures: the
  // query payoff's choices included).
  kill(pid_, SIGCONT);
  const unsigned char* data = image.pixels.data();
  std::size_t left = image.pixels.size();
  while (left > 0) {
    const ssize_t sent = send(socket_, data, left, MSG_NOSIGNAL);
    if (sent < 0 && errno == EINTR) continue;
    if (sent <= 0) {
      why_ = "ffmpeg stopped reading frames";
      stop();
      return;
    }
    data += sent;
    left -= static_cast<std::size_t>(sent);
  }
  kill(pid_, SIGSTOP);
  ++frames_;
}

bool VideoWriter::finish() {
  if (!ok()) return false;
  stop();
  if (WIFEXITED(status_) && WEXITSTATUS(status_) == 0) return true;
  why_ = fmt::format("ffmpeg exited with {}", WIFEXITED(status_) ? WEXITSTATUS(status_) : -1);
  log::warn("video: {}", why_);
  return false;
}

}  // namespace forest::app
