#include "core/source.h"

#include <filesystem>

namespace sscs {

Sources::Sources() { files_.push_back({"<none>", "", true}); }

uint32_t Sources::find(std::string_view path) const {
  for (uint32_t f = 1; f < files_.size(); ++f)
    if (files_[f].path == path) return f;
  return 0;
}

const std::string* Sources::unsaved(std::string_view path) const {
  if (!unsaved_ || unsaved_->empty()) return nullptr;
  std::error_code ec;
  const std::string key = std::filesystem::absolute(std::filesystem::path(path), ec).lexically_normal().string();
  auto it = unsaved_->find(key);
  return it == unsaved_->end() ? nullptr : &it->second;
}

uint32_t Sources::add(std::string path, std::string text) {
  files_.push_back({std::move(path), std::move(text)});
  for (char c : files_.back().text) files_.back().ascii &= static_cast<unsigned char>(c) < 0x80;
  return static_cast<uint32_t>(files_.size() - 1);
}

std::string_view Sources::line(const SourceMark& mark) const {
  if (mark.file == 0 || mark.file >= files_.size() || mark.line == 0) return {};
  std::string_view text = files_[mark.file].text;
  size_t pos = 0;
  for (uint32_t l = 1; l < mark.line; ++l) {
    pos = text.find('\n', pos);
    if (pos == std::string_view::npos) return {};
    ++pos;
  }
  size_t end = text.find('\n', pos);
  std::string_view line = text.substr(pos, end == std::string_view::npos ? text.size() - pos : end - pos);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

size_t characters(std::string_view text, size_t bytes) {
  size_t n = 0;
  for (size_t i = 0; i < bytes && i < text.size(); ++i) n += (static_cast<unsigned char>(text[i]) & 0xC0) != 0x80;
  return n + (bytes > text.size() ? bytes - text.size() : 0);
}

uint32_t Sources::character_column(const SourceMark& mark) const {
  if (mark.column == 0 || mark.file >= files_.size() || files_[mark.file].ascii) return mark.column;
  return static_cast<uint32_t>(characters(line(mark), mark.column - 1) + 1);
}

}  // namespace sscs
