#include "garmcap/pipeline/product_images.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

using namespace garmcap::pipeline;

TEST(ProductImages, GarmentIsCentredSquareAndKeepsItsColour) {
  cv::Mat frame(600, 800, CV_8UC3, cv::Scalar(40, 200, 40));
  cv::Mat mask = cv::Mat::zeros(frame.size(), CV_8UC1);
  cv::rectangle(mask, cv::Rect(100, 50, 200, 400), cv::Scalar(255), cv::FILLED);
  frame.setTo(cv::Scalar(30, 60, 200), mask);

  const ProductImages p = makeProductImages(frame, mask, {.sizePx = 300});
  ASSERT_EQ(p.onWhite.rows, 300);
  ASSERT_EQ(p.onWhite.cols, 300);
  ASSERT_EQ(p.transparent.type(), CV_8UC4);
  // Centre pixel is garment colour; corners are white / transparent; no green survives.
  const cv::Vec3b centre = p.onWhite.at<cv::Vec3b>(150, 150);
  EXPECT_NEAR(centre[0], 30, 2);
  EXPECT_NEAR(centre[2], 200, 2);
  EXPECT_EQ(p.onWhite.at<cv::Vec3b>(0, 0), cv::Vec3b(255, 255, 255));
  EXPECT_EQ(p.transparent.at<cv::Vec4b>(0, 0)[3], 0);
  cv::Mat hsv;
  cv::cvtColor(p.onWhite, hsv, cv::COLOR_BGR2HSV);
  cv::Mat green;
  cv::inRange(hsv, cv::Scalar(45, 100, 50), cv::Scalar(80, 255, 255), green);
  EXPECT_EQ(cv::countNonZero(green), 0);
  // Garment is centred horizontally: equal white margins left and right.
  cv::Mat alpha;
  cv::extractChannel(p.transparent, alpha, 3);
  const cv::Rect box = cv::boundingRect(alpha > 128);
  EXPECT_NEAR(box.x, 300 - (box.x + box.width), 2);
}

TEST(ProductImages, NeverUpscalesAndRejectsEmptyMask) {
  cv::Mat frame(100, 100, CV_8UC3, cv::Scalar(0, 0, 255));
  cv::Mat mask = cv::Mat::zeros(frame.size(), CV_8UC1);
  EXPECT_THROW(makeProductImages(frame, mask), std::invalid_argument);
  cv::rectangle(mask, cv::Rect(10, 10, 50, 60), cv::Scalar(255), cv::FILLED);
  const ProductImages p = makeProductImages(frame, mask, {.sizePx = 2000});
  EXPECT_LT(p.onWhite.cols, 100);
}
