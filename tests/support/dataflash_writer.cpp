#include "support/dataflash_writer.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace rangecal::test {
namespace {

int char_size(char c) {
  switch (c) {
    case 'b':
    case 'B':
    case 'M':
      return 1;
    case 'h':
    case 'H':
    case 'c':
    case 'C':
      return 2;
    case 'i':
    case 'I':
    case 'f':
    case 'e':
    case 'E':
    case 'L':
    case 'n':
      return 4;
    case 'd':
    case 'q':
    case 'Q':
      return 8;
    case 'N':
      return 16;
    case 'Z':
    case 'a':
      return 64;
  }
  throw std::invalid_argument(std::string("DataflashWriter: unknown format character ") + c);
}

void put_le(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
}

void put_text(std::string& out, const std::string& s, std::size_t size) {
  std::string t = s.substr(0, size);
  t.resize(size, '\0');
  out += t;
}

}  // namespace

DataflashWriter::DataflashWriter() {
  define(128, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");
}

void DataflashWriter::define(int type, const std::string& name, const std::string& format,
                             const std::string& columns, int length) {
  int size = 3;
  for (char c : format) size += char_size(c);
  bytes_ += "\xA3\x95\x80";
  bytes_ += static_cast<char>(type);
  bytes_ += static_cast<char>(length ? length : size);
  put_text(bytes_, name, 4);
  put_text(bytes_, format, 16);
  put_text(bytes_, columns, 64);
  formats_.at(static_cast<std::size_t>(type)) = format;
}

void DataflashWriter::message(int type, const std::vector<double>& values) {
  const std::string& format = formats_.at(static_cast<std::size_t>(type));
  if (values.size() != format.size()) throw std::invalid_argument("DataflashWriter: value count");
  bytes_ += "\xA3\x95";
  bytes_ += static_cast<char>(type);
  for (std::size_t i = 0; i < format.size(); ++i) {
    const char c = format[i];
    double v = values[i];
    if (c == 'c' || c == 'C' || c == 'e' || c == 'E') v *= 100;
    if (c == 'L') v *= 1e7;
    const int n = char_size(c);
    if (c == 'f') {
      const float f = static_cast<float>(v);
      std::uint32_t bits;
      static_assert(sizeof bits == sizeof f);
      std::memcpy(&bits, &f, sizeof f);
      put_le(bytes_, bits, 4);
    } else if (c == 'd') {
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof v);
      put_le(bytes_, bits, 8);
    } else if (c == 'n' || c == 'N' || c == 'Z' || c == 'a') {
      put_text(bytes_, "", static_cast<std::size_t>(n));
    } else {
      put_le(bytes_, static_cast<std::uint64_t>(std::llround(v)), n);
    }
  }
}

void DataflashWriter::define_att_and_gps() {
  define(kAtt, "ATT", "QffffffffB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
  define(kGps, "GPS", "QBBIHBcLLeffffB", "TimeUS,I,Status,GMS,GWk,NSats,HDop,Lat,Lng,Alt,Spd,GCrs,VZ,Yaw,U");
}

void DataflashWriter::att(std::uint64_t time_us, double roll, double pitch, double yaw) {
  message(kAtt, {static_cast<double>(time_us), 0, roll, 0, pitch, 0, yaw, 0, 0, 1});
}

void DataflashWriter::gps(std::uint64_t time_us, int status, int week, std::uint32_t week_ms, int instance) {
  message(kGps, {static_cast<double>(time_us), static_cast<double>(instance), static_cast<double>(status),
                 static_cast<double>(week_ms), static_cast<double>(week), 12, 0.8, 53.28, -8.98, 87.4, 5, 90,
                 0, 0, 1});
}

}  // namespace rangecal::test
