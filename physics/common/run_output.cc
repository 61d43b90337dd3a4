#include "common/run_output.h"

#include "temporary_files.h"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace physics
{
  JsonLinesLog::JsonLinesLog(const std::string& file)
      : file_(file)
      , out_(file, std::ios::trunc)
  {
    if (!out_)
      throw std::runtime_error(file + ": cannot open the run log for writing");
  }

  std::string JsonLinesLog::content() const
  {
    if (!out_.is_open())
      return "";
    std::ifstream      in(file_, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  void JsonLinesLog::restore(const std::string& content)
  {
    if (!out_.is_open())
      return;
    out_.close();
    write_atomically(file_, [&](std::ostream& out) { out << content; });
    out_.open(file_, std::ios::app);
    if (!out_)
      throw std::runtime_error(file_ + ": cannot reopen the run log for writing");
  }

  void JsonLinesLog::Line::key(const std::string& k)
  {
    if (!body_.empty())
      body_ += ", ";
    body_ += "\"" + json_escape(k) + "\": ";
  }

  JsonLinesLog::Line& JsonLinesLog::Line::add(const std::string& k, double value)
  {
    key(k);
    if (!std::isfinite(value))
      body_ += "null";
    else
      {
        std::ostringstream s;
        s << std::setprecision(10) << value;
        body_ += s.str();
      }
    return *this;
  }

  JsonLinesLog::Line& JsonLinesLog::Line::add(const std::string& k, long long value)
  {
    key(k);
    body_ += std::to_string(value);
    return *this;
  }

  JsonLinesLog::Line& JsonLinesLog::Line::add(const std::string& k, const std::vector<long long>& values)
  {
    key(k);
    body_ += "[";
    for (std::size_t i = 0; i < values.size(); ++i)
      body_ += (i ? "," : "") + std::to_string(values[i]);
    body_ += "]";
    return *this;
  }

  JsonLinesLog::Line& JsonLinesLog::Line::add(const std::string& k, bool value)
  {
    key(k);
    body_ += value ? "true" : "false";
    return *this;
  }

  JsonLinesLog::Line& JsonLinesLog::Line::add(const std::string& k, const std::string& value)
  {
    key(k);
    body_ += "\"" + json_escape(value) + "\"";
    return *this;
  }

  void JsonLinesLog::write(const Line& line)
  {
    if (!out_.is_open())
      return;
    const std::string text = line.str() + "\n";
    out_.write(text.data(), static_cast<std::streamsize>(text.size()));
    out_.flush();
  }

  void write_atomically(const std::string& file, const std::function<void(std::ostream&)>& content)
  {
    const std::string tmp = multigrid::unique_temporary_name(file);
    {
      std::ofstream out(tmp, std::ios::trunc);
      if (!out)
        throw std::runtime_error(file + ": cannot write");
      content(out);
      if (!out)
        throw std::runtime_error(file + ": write failed");
    }
    if (std::rename(tmp.c_str(), file.c_str()) != 0)
      throw std::runtime_error(file + ": cannot rename " + tmp);
  }

  void PvdSeries::add(double time, const std::string& pvtu)
  {
    entries_.emplace_back(time, pvtu);
    write_atomically(file_, [&](std::ostream& out) {
      out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          << "  <Collection>\n";
      for (const auto& [t, f] : entries_)
        out << "    <DataSet timestep=\"" << std::setprecision(12) << t << "\" group=\"\" part=\"0\" file=\"" << f
            << "\"/>\n";
      out << "  </Collection>\n</VTKFile>\n";
    });
  }

  std::string PvdSeries::entries() const
  {
    std::ostringstream text;
    text << std::setprecision(17);
    for (const auto& [t, f] : entries_)
      text << t << " " << f << "\n";
    return text.str();
  }

  void PvdSeries::restore(const std::string& entries)
  {
    entries_.clear();
    std::istringstream in(entries);
    double             t;
    std::string        f;
    while (in >> t >> f)
      entries_.emplace_back(t, f);
    if (entries_.empty())
      return;
    const auto last = entries_.back();
    entries_.pop_back();
    add(last.first, last.second); // rewrites the index
  }

  std::string json_escape(const std::string& s)
  {
    std::string r;
    for (char c : s)
      {
        if (c == '"' || c == '\\')
          r += std::string("\\") + c;
        else if (static_cast<unsigned char>(c) < 0x20)
          {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            r += buf;
          }
        else
          r += c;
      }
    return r;
  }
} // namespace physics
