// A list that many holders share instead of copying: 100,000 robots of one
// type in a world file hold one list of their ranger's twelve transducers,
// not 100,000 (host-sim/sim/desc.h, RobotDesc::rangers), and every model
// that inherits a property from one define holds one list of its values
// (worldfile.h, Property::values). Copying it copies a pointer; changing it
// (push_back, edit) first gives the changed list its own copy when another
// shares it, so a change is never seen by another holder. Reading never
// copies: element access is const, and a change goes through edit() by name.
#pragma once

#include <algorithm>
#include <cstddef>
#include <initializer_list>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

namespace troupe::world {

template <class T>
class SharedList {
 public:
  using value_type = T;
  using const_iterator = const T*;

  SharedList() = default;
  SharedList(std::initializer_list<T> items) {
    if (items.size() > 0) items_ = std::make_shared<std::vector<T>>(items);
  }
  explicit SharedList(std::vector<T> items) {
    if (!items.empty()) items_ = std::make_shared<std::vector<T>>(std::move(items));
  }

  size_t size() const { return items_ ? items_->size() : 0; }
  bool empty() const { return size() == 0; }
  const T* data() const { return items_ ? items_->data() : nullptr; }
  const T* begin() const { return data(); }
  const T* end() const { return data() + size(); }
  const T& operator[](size_t i) const { return (*items_)[i]; }
  /// Throws std::out_of_range past the end, as std::vector::at.
  const T& at(size_t i) const {
    if (i >= size()) throw std::out_of_range("SharedList::at");
    return (*items_)[i];
  }
  const T& front() const { return (*items_)[0]; }
  const T& back() const { return (*items_)[size() - 1]; }

  /// Item i, to change: the list is this one's alone from then on.
  T& edit(size_t i) { return own().at(i); }
  T& edit_back() { return own().back(); }
  void push_back(T item) { own().push_back(std::move(item)); }
  template <class... Args>
  T& emplace_back(Args&&... args) {
    return own().emplace_back(std::forward<Args>(args)...);
  }
  /// Inserts [first, last) before `pos` (an iterator of this list).
  template <class It>
  void insert(const T* pos, It first, It last) {
    const size_t at = size_t(pos - begin());
    std::vector<T>& items = own();
    items.insert(items.begin() + std::ptrdiff_t(at), first, last);
  }
  void clear() { items_.reset(); }

  /// Equal items (a list shared with itself is equal without comparing).
  bool operator==(const SharedList& o) const {
    return items_ == o.items_ || std::equal(begin(), end(), o.begin(), o.end());
  }
  /// True when both hold the one list in memory.
  bool shares_with(const SharedList& o) const { return items_ != nullptr && items_ == o.items_; }

 private:
  std::vector<T>& own() {
    if (!items_) {
      items_ = std::make_shared<std::vector<T>>();
    } else if (items_.use_count() > 1) {
      items_ = std::make_shared<std::vector<T>>(*items_);
    }
    return *items_;
  }

  std::shared_ptr<std::vector<T>> items_;
};

}  // namespace troupe::world
