"""Models: generic demonstration trees and the Bo105 helicopter."""
