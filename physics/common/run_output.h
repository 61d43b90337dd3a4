// Run output shared by every app: a JSON-lines solver log and a ParaView .pvd series of
// per-step .pvtu records. Both are written so that an interrupted run leaves only complete
// files behind: each log line goes out in one write() and is flushed; the .pvd index is
// rewritten to a temporary file and renamed after each step's .vtu/.pvtu files are complete,
// so it never lists a step that was not fully written.
#pragma once

#include <functional>
#include <fstream>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace physics
{
  /// Writes `content(stream)` to `file` through a run-private temporary file renamed into place
  /// when complete, so an interrupted run never leaves a partial file; throws std::runtime_error
  /// naming the file if it cannot be written.
  void write_atomically(const std::string& file, const std::function<void(std::ostream&)>& content);

  /// One JSON object per line. Only the rank that opened it writes (the others hold a closed log).
  class JsonLinesLog
  {
  public:
    JsonLinesLog() = default;
    /// Opens (truncates) `file`; throws std::runtime_error naming the file if it cannot.
    explicit JsonLinesLog(const std::string& file);
    bool is_open() const { return out_.is_open(); }
    const std::string& file() const { return file_; }
    /// The lines written so far (the file's content; "" on a closed log).
    std::string content() const;
    /// Replaces the file's content by `content` (atomically) and appends from there: a resumed
    /// run continues the log its checkpoint holds. No-op on a closed log.
    void restore(const std::string& content);

    /// Builder of one line: add fields, then write().
    class Line
    {
    public:
      Line& add(const std::string& key, double value);
      Line& add(const std::string& key, long long value);
      Line& add(const std::string& key, int value) { return add(key, static_cast<long long>(value)); }
      Line& add(const std::string& key, bool value);
      Line& add(const std::string& key, const std::string& value);
      Line&       add(const std::string& key, const std::vector<long long>& values); ///< a JSON array
      std::string str() const { return "{" + body_ + "}"; }

    private:
      void        key(const std::string& k);
      std::string body_;
    };
    void write(const Line& line);

  private:
    std::string   file_;
    std::ofstream out_;
  };

  /// The .pvd index of a time series of .pvtu records.
  class PvdSeries
  {
  public:
    explicit PvdSeries(std::string file)
        : file_(std::move(file))
    {
    }
    /// Adds (time, pvtu file name relative to the .pvd) and rewrites the index atomically.
    void add(double time, const std::string& pvtu);
    /// The entries so far, one "time file" line each, and back (checkpoint/restart; rewrites the
    /// index).
    std::string entries() const;
    void        restore(const std::string& entries);

  private:
    std::string                                  file_;
    std::vector<std::pair<double, std::string>> entries_;
  };

  /// JSON string escaping (quotes, backslashes, control characters).
  std::string json_escape(const std::string& s);
} // namespace physics
