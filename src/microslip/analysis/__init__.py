"""Analysis: free normal vibration and the steady stick–slip cycle."""
