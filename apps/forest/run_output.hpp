#pragma once
// What a multi-frame command leaves in its output folder: the files of one run only (an earlier
// run's files there are removed first), and a contact sheet sampled across the whole run.
#include <sys/types.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "forest/core/image.hpp"

namespace forest::app {

// Removes what an earlier run of the same command left in `folder`: the named files and, with
// framesFolder, frames/frame*.png. Nothing else is touched (a folder of other files stays as it
// was). Returns how many files were removed.
int clearEarlierRun(const std::filesystem::path& folder, const std::vector<std::string>& ownedFiles, bool framesFolder);
// The same for what walkthrough, its window mode and budget write (they share --out folders):
// frames/frame*.png, report.json, contact-sheet.png, walkthrough.mp4, window.png. Logs what it removed.
int clearEarlierWalk(const std::filesystem::path& folder);

// Thumbnails sampled evenly across a run of unknown length (it may be interrupted): every
// stride-th frame is kept, and when more than 2·max are kept every other one goes and the stride
// doubles. compose() lays out up to `max` of them, spread from the first frame to the last one
// given, four per row, each labelled with its frame number, path time and frame time. Thumbnails are
// the frame shrunk by the smallest integer factor that fits thumbnailWidth (box filter).
class ContactSheet {
 public:
  explicit ContactSheet(int maxThumbnails = 16, int thumbnailWidth = 320);
  bool wants(int frame) const { return frame % stride_ == 0; }
  // Adds a frame (replacing an earlier entry of the same frame number).
  void add(int frame, double timeSeconds, double frameMs, const Image8& image);
  bool has(int frame) const;
  bool empty() const { return kept_.empty(); }
  // The frames compose() shows, in order.
  std::vector<int> shownFrames() const;
  Image8 compose() const;

 private:
  struct Thumbnail {
    int frame;
    double time;
    double frameMs;
    Image8 image;
  };
  int max_, width_, stride_ = 1;
  std::vector<Thumbnail> kept_;
  std::vector<size_t> shownIndices() const;
};

// An MP4 of a run's frames as they are rendered (H.264, yuv420p), encoded by ffmpeg reading raw
// RGBA frames from a socket: no frame is written to disk first. ffmpeg is stopped (SIGSTOP) except
// while add() hands it a frame, when it encodes the one before: it never runs beside the frames the
// run measures. Its own process group: Ctrl-C stops the run, which still finishes the video of the
// frames done. yuv420p needs even sizes: an odd width or height gets one black row or column.
class VideoWriter {
 public:
  // Starts ffmpeg writing `file` at `fps`; without ffmpeg nothing starts (ok() false, why() says so).
  VideoWriter(const std::filesystem::path& file, int width, int height, double fps);
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;
  bool ok() const { return socket_ >= 0; }
  // Appends a frame (top row first, RGBA, the size given); a failed write stops the video.
  void add(const Image8& image);
  // Lets ffmpeg encode what is left and waits for it; true when the MP4 is complete. Else why().
  bool finish();
  const std::string& why() const { return why_; }
  int frames() const { return frames_; }

 private:
  void stop();  // closes the socket, lets ffmpeg run to its end and reaps it
  int socket_ = -1;
  pid_t pid_ = -1;
  int status_ = 0;
  int width_, height_, frames_ = 0;
  std::string why_;
};

// The line a benchmark's Markdown table starts with: "Measured YYYY-MM-DD on N cores of CPU; GL: device."
std::string benchmarkStamp(const std::string& device);

// `text` as one word for /bin/sh: in single quotes, each ' written as '\''.
std::string shellQuoted(const std::string& text);

}  // namespace forest::app
