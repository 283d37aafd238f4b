#include "model_writers.h"

#include <algorithm>
#include <cstring>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "reader_test_util.h"

namespace terramesh::test {
namespace {

using datasets::ColmapModel;

/// An ostringstream that prints doubles so that they read back bit for bit.
std::ostringstream exactStream() {
  std::ostringstream out;
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  return out;
}

/// Appends `value` to `out` in little-endian byte order.
template <class T>
void put(std::string& out, T value) {
  using Bits = std::conditional_t<sizeof(T) == 1, std::uint8_t,
                                  std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>;
  Bits bits = 0;
  std::memcpy(&bits, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i)
    out.push_back(static_cast<char>((bits >> (8 * i)) & 0xff));
}

std::vector<const datasets::ColmapImage*> imagesById(const ColmapModel& model) {
  std::vector<const datasets::ColmapImage*> images;
  for (const auto& image : model.images) images.push_back(&image);
  std::sort(images.begin(), images.end(), [](auto* a, auto* b) { return a->id < b->id; });
  return images;
}

}  // namespace

void writeColmapText(const std::filesystem::path& directory, const ColmapModel& model) {
  std::filesystem::create_directories(directory);
  auto cameras = exactStream();
  cameras << "# Camera list with one line of data per camera:\n";
  for (const auto& camera : model.cameras) {
    cameras << camera.id << ' ' << camera.model << ' ' << camera.width_px << ' '
            << camera.height_px;
    for (double param : camera.params) cameras << ' ' << param;
    cameras << '\n';
  }
  writeFile(directory / "cameras.txt", cameras.str());

  auto images = exactStream();
  images << "# Image list with two lines of data per image:\n";
  for (const auto& image : model.images) {
    const auto& q = image.rotation_C_W;
    const auto& t = image.translation_C_W;
    images << image.id << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' '
           << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << image.camera_id << ' ' << image.name
           << '\n';
    for (std::size_t k = 0; k < image.points2D_px.size(); ++k) {
      images << (k == 0 ? "" : " ") << image.points2D_px[k].x() << ' ' << image.points2D_px[k].y()
             << ' ' << image.point3D_ids[k];
    }
    images << '\n';
  }
  writeFile(directory / "images.txt", images.str());

  auto points = exactStream();
  points << "# 3D point list with one line of data per point:\n";
  for (const auto& point : model.points) {
    points << point.id << ' ' << point.position_W.x() << ' ' << point.position_W.y() << ' '
           << point.position_W.z() << ' ' << int{point.rgb[0]} << ' ' << int{point.rgb[1]} << ' '
           << int{point.rgb[2]} << ' ' << point.error_px;
    for (const auto& element : point.track) {
      points << ' ' << element.image_id << ' ' << element.point2D_index;
    }
    points << '\n';
  }
  writeFile(directory / "points3D.txt", points.str());
}

void writeColmapBinary(const std::filesystem::path& directory, const ColmapModel& model) {
  std::filesystem::create_directories(directory);
  std::string cameras;
  put<std::uint64_t>(cameras, model.cameras.size());
  for (const auto& camera : model.cameras) {
    const std::optional<int> model_id = datasets::colmapCameraModelId(camera.model);
    if (!model_id) throw std::invalid_argument("unknown camera model " + camera.model);
    put<std::uint32_t>(cameras, camera.id);
    put<std::int32_t>(cameras, *model_id);
    put<std::uint64_t>(cameras, camera.width_px);
    put<std::uint64_t>(cameras, camera.height_px);
    for (double param : camera.params) put<double>(cameras, param);
  }
  writeFile(directory / "cameras.bin", cameras);

  std::string images;
  put<std::uint64_t>(images, model.images.size());
  for (const auto& image : model.images) {
    put<std::uint32_t>(images, image.id);
    for (double value : {image.rotation_C_W.w(), image.rotation_C_W.x(), image.rotation_C_W.y(),
                         image.rotation_C_W.z()}) {
      put<double>(images, value);
    }
    for (int k = 0; k < 3; ++k) put<double>(images, image.translation_C_W[k]);
    put<std::uint32_t>(images, image.camera_id);
    images += image.name;
    images.push_back('\0');
    put<std::uint64_t>(images, image.points2D_px.size());
    for (std::size_t k = 0; k < image.points2D_px.size(); ++k) {
      put<double>(images, image.points2D_px[k].x());
      put<double>(images, image.points2D_px[k].y());
      put<std::int64_t>(images, image.point3D_ids[k]);
    }
  }
  writeFile(directory / "images.bin", images);

  std::string points;
  put<std::uint64_t>(points, model.points.size());
  for (const auto& point : model.points) {
    put<std::uint64_t>(points, point.id);
    for (int k = 0; k < 3; ++k) put<double>(points, point.position_W[k]);
    for (std::uint8_t channel : point.rgb) put<std::uint8_t>(points, channel);
    put<double>(points, point.error_px);
    put<std::uint64_t>(points, point.track.size());
    for (const auto& element : point.track) {
      put<std::uint32_t>(points, element.image_id);
      put<std::uint32_t>(points, element.point2D_index);
    }
  }
  writeFile(directory / "points3D.bin", points);
}

void writeBundlerFromColmap(const std::filesystem::path& bundle_path,
                            const std::filesystem::path& list_path, const ColmapModel& model) {
  const auto images = imagesById(model);
  std::map<std::uint32_t, std::size_t> camera_index;
  std::map<std::uint32_t, const datasets::ColmapCamera*> cameras;
  for (const auto& camera : model.cameras) cameras[camera.id] = &camera;
  const Eigen::Matrix3d flip_yz = Eigen::Vector3d(1, -1, -1).asDiagonal();

  auto out = exactStream();
  auto list = exactStream();
  out << "# Bundle file v0.3\n" << images.size() << ' ' << model.points.size() << '\n';
  for (std::size_t i = 0; i < images.size(); ++i) {
    const auto& image = *images[i];
    camera_index[image.id] = i;
    list << image.name << '\n';
    const Eigen::Matrix3d rotation = flip_yz * image.rotation_C_W.normalized().toRotationMatrix();
    const Eigen::Vector3d translation = flip_yz * image.translation_C_W;
    out << cameras.at(image.camera_id)->params.at(0) << " 0 0\n";
    for (int r = 0; r < 3; ++r) {
      out << rotation(r, 0) << ' ' << rotation(r, 1) << ' ' << rotation(r, 2) << '\n';
    }
    out << translation.x() << ' ' << translation.y() << ' ' << translation.z() << '\n';
  }
  std::map<std::uint32_t, const datasets::ColmapImage*> by_id;
  for (const auto* image : images) by_id[image->id] = image;
  for (const auto& point : model.points) {
    out << point.position_W.x() << ' ' << point.position_W.y() << ' ' << point.position_W.z()
        << '\n'
        << int{point.rgb[0]} << ' ' << int{point.rgb[1]} << ' ' << int{point.rgb[2]} << '\n'
        << point.track.size();
    for (const auto& element : point.track) {
      const auto& xy = by_id.at(element.image_id)->points2D_px.at(element.point2D_index);
      out << ' ' << camera_index.at(element.image_id) << ' ' << element.point2D_index << ' '
          << xy.x() << ' ' << -xy.y();
    }
    out << '\n';
  }
  writeFile(bundle_path, out.str());
  writeFile(list_path, list.str());
}

std::filesystem::path writeOpenSfmBundlerExport(const std::filesystem::path& directory,
                                                const ColmapModel& model) {
  const std::filesystem::path bundle = directory / "bundle_r000.out";
  const std::filesystem::path list = directory / "list_r000.out";
  writeBundlerFromColmap(bundle, list, model);
  // OpenSfM's list has the image's path relative to the dataset, then 0 and the focal length.
  std::map<std::uint32_t, const datasets::ColmapCamera*> cameras;
  for (const auto& camera : model.cameras) cameras[camera.id] = &camera;
  auto out = exactStream();
  for (const auto* image : imagesById(model)) {
    out << "images/" << image->name << " 0 " << cameras.at(image->camera_id)->params.at(0) << '\n';
  }
  writeFile(list, out.str());
  return bundle;
}

}  // namespace terramesh::test
