#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "pipeline/primitive_seed.hpp"

namespace tlsmon {

std::optional<PrimitiveSeed> ransac_primitive(primitives::Kind kind, const SurfaceSample& sample,
                                              const PrimitiveSeedParams& params) {
    if (sample.points.size() < 8) return std::nullopt;
    // About the sample's centroid, in float (as pipeline/pcl_adapter.cpp).
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    for (const auto& p : sample.points) origin += p;
    origin /= static_cast<double>(sample.points.size());
    pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
    pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
    for (std::size_t i = 0; i < sample.points.size(); ++i) {
        const Eigen::Vector3f p = (sample.points[i] - origin).cast<float>();
        const Eigen::Vector3f n = sample.normals[i].cast<float>();
        cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
        normals->push_back(pcl::Normal(n.x(), n.y(), n.z()));
    }
    pcl::SACSegmentationFromNormals<pcl::PointXYZ, pcl::Normal> seg;
    seg.setOptimizeCoefficients(true);
    seg.setModelType(kind == primitives::Kind::plane      ? pcl::SACMODEL_NORMAL_PLANE
                     : kind == primitives::Kind::cylinder ? pcl::SACMODEL_CYLINDER
                                                          : pcl::SACMODEL_NORMAL_SPHERE);
    seg.setMethodType(pcl::SAC_RANSAC);
    seg.setNormalDistanceWeight(params.normal_weight);
    seg.setMaxIterations(params.iterations);
    seg.setDistanceThreshold(params.threshold);
    if (kind != primitives::Kind::plane) seg.setRadiusLimits(params.min_radius, params.max_radius);
    seg.setInputCloud(cloud);
    seg.setInputNormals(normals);
    pcl::PointIndices inliers;
    pcl::ModelCoefficients model;
    seg.segment(inliers, model);
    if (inliers.indices.empty()) return std::nullopt;
    const auto& c = model.values;
    PrimitiveSeed seed;
    seed.inliers = inliers.indices.size();
    switch (kind) {
        case primitives::Kind::plane: {
            // a·x + b·y + c·z + d = 0 about the origin: its foot point from the origin.
            const Eigen::Vector3d n(c[0], c[1], c[2]);
            const double len = n.norm();
            seed.primitive = primitives::plane_through(origin - n * (c[3] / (len * len)), n);
            break;
        }
        case primitives::Kind::cylinder: {
            Eigen::Vector3d point(c[0], c[1], c[2]);
            const Eigen::Vector3d axis = Eigen::Vector3d(c[3], c[4], c[5]).normalized();
            // The axis point nearest the sample's centroid (the frame's origin).
            point -= axis * axis.dot(point);
            seed.primitive = primitives::cylinder_about(origin + point, axis, c[6]);
            break;
        }
        case primitives::Kind::sphere:
            seed.primitive =
                primitives::sphere_at(origin + Eigen::Vector3d(c[0], c[1], c[2]), c[3]);
            break;
    }
    return seed;
}

}  // namespace tlsmon
