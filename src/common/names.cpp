#include "railvib/common/names.hpp"

#include <sstream>
#include <stdexcept>

namespace railvib::names {

std::string receiverLinePoint(double y_m) {
  std::ostringstream name;
  name << "line_y" << y_m;
  return name.str();
}

std::string buildingPlanPoint(int row, int column) {
  static const char* const kNames[3][3] = {{"bldg_front_left", "bldg_front_mid", "bldg_front_right"},
                                           {"bldg_mid_left", "bldg_centre", "bldg_mid_right"},
                                           {"bldg_back_left", "bldg_back_mid", "bldg_back_right"}};
  if (row < 0 || row > 2 || column < 0 || column > 2) throw std::out_of_range("buildingPlanPoint: row/column 0..2");
  return kNames[row][column];
}

}  // namespace railvib::names
