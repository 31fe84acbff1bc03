#include "numerics/problems.hpp"

namespace yarnfit::numerics {

std::string Problem::to_string() const {
  std::string out = file;
  if (line > 0) out += ":" + std::to_string(line);
  if (!out.empty()) out += ": ";
  out += (field.empty() ? std::string("file") : field) + ": " + message;
  return out;
}

void Problems::add(std::string file, int line, std::string field, std::string message) {
  m_items.push_back(Problem{std::move(file), line, std::move(field), std::move(message)});
}

void Problems::append(const Problems& other) {
  m_items.insert(m_items.end(), other.m_items.begin(), other.m_items.end());
}

void Problems::append(const Problems& other, const std::string& prefix) {
  for (const auto& p : other.m_items) add(p.file, p.line, prefix + p.field, p.message);
}

std::string Problems::to_string() const {
  std::string out;
  for (const auto& p : m_items) out += p.to_string() + "\n";
  return out;
}

std::string Problems::one_line() const {
  std::string out;
  for (const auto& p : m_items) out += (out.empty() ? "" : "; ") + p.to_string();
  return out;
}

}  // namespace yarnfit::numerics
